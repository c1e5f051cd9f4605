#version 450
// Counting frames (illum-bench raster): the 2×2 quads a scene pass shades. GPUs run
// fragment shaders in quads — a triangle that covers one sample of a quad still occupies
// all four lanes — so a pass of small triangles does more fragment work than its samples
// say. Drawn with the pass's own vertex stage and depth state, early tests forced, this
// shader counts the samples that passed (the occlusion query's count, as a check) and the
// quads that hold at least one of them, each quad once: by its lowest live lane. Helper
// lanes take part in quad operations but their stores are discarded, so only live lanes
// add.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_quad : require

layout(early_fragment_tests) in;

layout(std430, set = 2, binding = 0) buffer QuadCounter {
  uint quads;
  uint samples;
} counter;

void main() {
  const uint live = gl_HelperInvocation ? 0u : 1u;
  const uint lanes = subgroupQuadBroadcast(live, 0) | (subgroupQuadBroadcast(live, 1) << 1) |
                     (subgroupQuadBroadcast(live, 2) << 2) | (subgroupQuadBroadcast(live, 3) << 3);
  const uint me = gl_SubgroupInvocationID & 3u;
  if (live == 0u) return;
  atomicAdd(counter.samples, 1u);
  if ((lanes & ((1u << me) - 1u)) == 0u) atomicAdd(counter.quads, 1u);
}
