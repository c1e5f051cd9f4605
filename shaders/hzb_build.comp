#version 450
// Up to four levels of the hierarchical max-depth buffer (shaders/occlusion.glsl) in one
// dispatch: each texel is the largest of the 2×2 texels under it in the level below (level 0:
// of the depth target). Max, not min: a box is hidden only if it lies behind the farthest
// depth of every pixel it may cover. A 16 × 16 group makes 16² texels of the first level,
// then 8², 4² and 2² of the next ones from shared memory: a texel's 2×2 sources lie in its
// group's block (clamping at the level's edge stays inside it), so one dispatch per four
// levels, not one per level (a 1080p pyramid: 3 dispatches instead of 11).
#include "occlusion.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

shared float tile[16][16];

// The largest of the 2×2 texels of level `level` − 1 (the depth target for level 0) under
// texel `p` of `level`; clamping to the level's edge repeats a texel that is under it anyway.
float reduce_below(uvec2 extent, uint level, uvec2 p) {
  const uvec2 below = level == 0u ? extent : hzb_size(extent, level - 1u);
  const uint below_offset = level == 0u ? 0u : hzb_offset(extent, level - 1u);
  float farthest = 0.0;
  for (uint k = 0u; k < 4u; ++k) {
    const uvec2 q = min(2u * p + uvec2(k & 1u, k >> 1u), below - 1u);
    const float d = level == 0u ? texelFetch(depth_target, ivec2(q), 0).r
                                : hzb[below_offset + q.y * below.x + q.x];
    farthest = max(farthest, d);
  }
  return farthest;
}

void main() {
  const uvec2 extent = push.extent.xy;
  const uint first = push.extent.z, levels = push.extent.w;
  const uvec2 l = gl_LocalInvocationID.xy, g = gl_WorkGroupID.xy;
  uvec2 size = hzb_size(extent, first);
  const uvec2 p = 16u * g + l;
  float v = 0.0;
  if (p.x < size.x && p.y < size.y) {
    v = reduce_below(extent, first, p);
    hzb[hzb_offset(extent, first) + p.y * size.x + p.x] = v;
  }
  tile[l.y][l.x] = v;
  for (uint k = 1u; k < levels; ++k) {
    barrier();
    const uint n = 16u >> k;  // this level's texels per group side
    const uvec2 below = size;
    size = hzb_size(extent, first + k);
    const uvec2 q = n * g + l;
    const bool mine = l.x < n && l.y < n;
    float w = 0.0;
    if (mine && q.x < size.x && q.y < size.y) {
      for (uint c = 0u; c < 4u; ++c) {
        const uvec2 s = min(2u * q + uvec2(c & 1u, c >> 1u), below - 1u) - 2u * n * g;
        w = max(w, tile[s.y][s.x]);
      }
      hzb[hzb_offset(extent, first + k) + q.y * size.x + q.x] = w;
    }
    barrier();
    if (mine) tile[l.y][l.x] = w;
  }
}
