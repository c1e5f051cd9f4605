#version 450
// The occlusion test of every cluster a view's CPU pass listed (realtime/occlusion_culling.h),
// between the two halves of the pass: the first half drew the clusters visible last frame
// (visible[parity]); this writes the clusters visible now (visible[1 − parity]) and the second
// half's flags (visible now and not drawn by the first), and counts what the two halves drew.
//
// Conservative: a cluster is hidden only when the nearest depth of its bounding box lies
// behind the farthest depth (HZB) of every pixel its screen rectangle touches, so whatever
// it would have drawn fails the depth test (LESS, depth cleared to 1). Boxes that reach the
// near plane (or behind the eye) are visible.
#include "occlusion.glsl"

layout(local_size_x = 64) in;

bool visible(uint c) {
  const ClusterBounds b = clusters[c];
  vec3 lo = vec3(1e30), hi = vec3(-1e30);  // screen rectangle (NDC xy) and depth range
  for (uint k = 0u; k < 8u; ++k) {
    const vec3 p = vec3((k & 1u) != 0u ? b.hi.x : b.lo.x, (k & 2u) != 0u ? b.hi.y : b.lo.y,
                        (k & 4u) != 0u ? b.hi.z : b.lo.z);
    const vec4 h = push.clip * vec4(p, 1.0);
    if (h.w <= 1e-6 || h.z <= 0.0) return true;  // reaches the near plane
    const vec3 ndc = h.xyz / h.w;
    lo = min(lo, ndc);
    hi = max(hi, ndc);
  }
  const vec2 extent = vec2(push.extent.xy);
  // Pixels whose centres the rectangle may cover, one pixel wider on each side against
  // rounding; clamped to the target.
  const vec2 a = (lo.xy * 0.5 + 0.5) * extent - 1.0;
  const vec2 z = (hi.xy * 0.5 + 0.5) * extent + 1.0;
  if (z.x < 0.0 || z.y < 0.0 || a.x >= extent.x || a.y >= extent.y) return false;  // off screen
  const uvec2 p0 = uvec2(clamp(a, vec2(0.0), extent - 1.0));
  const uvec2 p1 = uvec2(clamp(z, vec2(0.0), extent - 1.0));
  // The finest level where the rectangle touches at most 2×2 texels.
  uint level = 0u;
  uvec2 t0 = p0 >> 1u, t1 = p1 >> 1u;
  while (t1.x - t0.x > 1u || t1.y - t0.y > 1u) {
    ++level;
    t0 >>= 1u;
    t1 >>= 1u;
  }
  const uvec2 size = hzb_size(push.extent.xy, level);
  const uint offset = hzb_offset(push.extent.xy, level);
  float farthest = 0.0;
  for (uint y = t0.y; y <= min(t1.y, size.y - 1u); ++y)
    for (uint x = t0.x; x <= min(t1.x, size.x - 1u); ++x)
      farthest = max(farthest, hzb[offset + y * size.x + x]);
  // The box's nearest depth against it, with a margin for the rounding of the vertex
  // transform the rasterizer's depths came from (a surface coplanar with the one that wrote
  // the HZB stays visible).
  return lo.z <= farthest + 1e-6;
}

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= push.config.x) return;
  const uint c = listed[i];
  const bool first_half = (push.config.y == 0u ? visible0[c] : visible1[c]) != 0u;
  const bool now = visible(c);
  if (push.config.y == 0u)
    visible1[c] = now ? 1u : 0u;
  else
    visible0[c] = now ? 1u : 0u;
  const bool second_half = now && !first_half;
  late[c] = second_half ? 1u : 0u;
  const uint triangles = floatBitsToUint(clusters[c].lo.w);
  if (first_half || second_half) {
    atomicAdd(stats[0], triangles);
    atomicAdd(stats[1], 1u);
  }
  if (now) {
    atomicAdd(stats[2], triangles);
    atomicAdd(stats[3], 1u);
  }
}
