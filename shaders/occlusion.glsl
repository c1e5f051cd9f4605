// Occlusion culling of clusters (realtime/occlusion_culling.h): the hierarchical max-depth
// buffer (HZB) and the per-view flags, shared by hzb_build.comp and occlusion_cull.comp.
//
// HZB level 0 is half the depth target's size (each texel the largest depth of its 2×2
// block), level k+1 half of level k, rounding up, down to 1×1; a texel of level k covers
// the pixels [x·2^(k+1), (x+1)·2^(k+1)) (clamped at the edges), so the largest depth under
// any pixel rectangle is the largest of the texels it touches at any level. All levels lie
// one after the other in one float buffer.

layout(set = 0, binding = 0) uniform sampler2D depth_target;
layout(std430, set = 0, binding = 1) buffer Hzb { float hzb[]; };
// Per cluster: world-space bounds, its triangle count in lo.w (as bits).
struct ClusterBounds {
  vec4 lo;
  vec4 hi;
};
layout(std430, set = 0, binding = 2) readonly buffer Clusters { ClusterBounds clusters[]; };
// visible[0] and visible[1]: "visible" flags of two frames, one uint per cluster (ping-pong:
// push.config.y names the one the first half was predicated on).
layout(std430, set = 0, binding = 3) buffer Visible0 { uint visible0[]; };
layout(std430, set = 0, binding = 4) buffer Visible1 { uint visible1[]; };
layout(std430, set = 0, binding = 5) buffer Late { uint late[]; };      // second-half flags
layout(std430, set = 0, binding = 6) readonly buffer List { uint listed[]; };  // drawn by the CPU
// {triangles, clusters} drawn by the two halves, then {triangles, clusters} finally visible.
layout(std430, set = 0, binding = 7) buffer Stats { uint stats[4]; };

layout(push_constant) uniform Push {
  mat4 clip;      // occlusion_cull: the view's world-to-clip transform
  uvec4 config;   // x: count (clusters listed / texels of the level built), y: parity, z: flags
  uvec4 extent;   // xy: the depth target's size; hzb_build: z = the first level built, w = how many
} push;

// Size of HZB level `level` for a depth target of `extent`.
uvec2 hzb_size(uvec2 extent, uint level) {
  uvec2 s = (extent + 1u) / 2u;
  for (uint k = 0u; k < level; ++k) s = (s + 1u) / 2u;
  return s;
}

// Offset (in floats) of level `level` in the HZB buffer.
uint hzb_offset(uvec2 extent, uint level) {
  uint offset = 0u;
  uvec2 s = (extent + 1u) / 2u;
  for (uint k = 0u; k < level; ++k) {
    offset += s.x * s.y;
    s = (s + 1u) / 2u;
  }
  return offset;
}
