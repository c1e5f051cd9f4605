#version 450
// One level of the hierarchical max-depth buffer (shaders/occlusion.glsl): each texel is the
// largest of the 2×2 texels under it in the level below (level 0: of the depth target).
// Max, not min: a box is hidden only if it lies behind the farthest depth of every pixel it
// may cover.
#include "occlusion.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  const uvec2 extent = push.extent.xy;
  const uint level = push.extent.z;
  const uvec2 size = hzb_size(extent, level);
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= size.x || p.y >= size.y) return;
  // The level below: the depth target itself for level 0. Clamping to its edge repeats a
  // texel that is under this one anyway.
  const uvec2 below = level == 0u ? extent : hzb_size(extent, level - 1u);
  const uint below_offset = level == 0u ? 0u : hzb_offset(extent, level - 1u);
  float farthest = 0.0;
  for (uint k = 0u; k < 4u; ++k) {
    const uvec2 q = min(2u * p + uvec2(k & 1u, k >> 1u), below - 1u);
    const float d = level == 0u ? texelFetch(depth_target, ivec2(q), 0).r
                                : hzb[below_offset + q.y * below.x + q.x];
    farthest = max(farthest, d);
  }
  hzb[hzb_offset(extent, level) + p.y * size.x + p.x] = farthest;
}
