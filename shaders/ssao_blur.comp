#version 450
// The raw SSAO (one estimate per pixel, or at half resolution per 2×2 pixels) to the
// full-resolution AO: a depth-aware (bilateral) gather over the texels
// around the pixel's own — a neighbour counts with weight exp(−(Δ/σ)²)·max(n·n_i, 0)⁸, Δ the
// pixel's distance from the texel's plane and σ = R/10 — so occlusion neither bleeds across
// silhouettes or creases nor is taken from another surface when upsampling.
// Blur radius r (pixels): a (2r'+1)² window of texels, r' = r at full resolution, ⌈r/2⌉ at
// half. r = 0: no blur — full resolution copies; half resolution takes the pixel's own texel
// where it lies on the pixel's surface, else the best-weighted of its 3×3 neighbours.
// A group's windows overlap: their estimates (planes and AO) are read once into shared memory.
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, r32f) uniform writeonly image2D ao_out;

// The window of a group: its 8×8 pixels' own estimates and `reach` around them, reach ≤ 8 (blur
// radius ≤ 8 at full resolution, ⌈8/2⌉ at half).
const int kMaxTile = 8 + 2 * 8;
shared uvec4 tile[kMaxTile * kMaxTile];  // plane x, y, z; w: the AO's bits

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  int divisor = ssao.grid.x;
  ivec2 size = ssao.grid.zw;
  int r = ssao.info.y;
  int reach = r == 0 ? 1 : (divisor == 1 ? r : (r + 1) / 2);
  // The group's own estimates lie in [first, first + 8/divisor) (min is monotonic).
  ivec2 tile_origin = min(ivec2(gl_WorkGroupID.xy) * 8 / divisor, size - 1) - reach;
  int side = 8 / divisor + 2 * reach;
  // (Without blur at full resolution each pixel copies its own estimate: no window.)
  int loads = r == 0 && divisor == 1 ? 0 : side * side;
  for (int i = int(gl_LocalInvocationIndex); i < loads; i += 64) {
    ivec2 q = tile_origin + ivec2(i % side, i / side);
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) {
      tile[i] = uvec4(floatBitsToUint(-1.0), 0u, 0u, 0u);  // skipped as the sky is
      continue;
    }
    uvec4 v = texelFetch(ssao_planes, ssao_representative(q), 0);
    tile[i] = uvec4(v.xyz, floatBitsToUint(texelFetch(ssao_source, q, 0).r));
  }
  memoryBarrierShared();
  barrier();
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  ivec2 own = min(pixel / divisor, size - 1);
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  uvec4 own_plane = texelFetch(ssao_planes, pixel, 0);
  if (depth >= 1.0) {
    imageStore(ao_out, pixel, vec4(1.0));
    return;
  }
  if (r == 0 && divisor == 1) {
    imageStore(ao_out, pixel, vec4(texelFetch(ssao_source, own, 0).r));
    return;
  }
  vec3 p = ssao_position(vec2(pixel) + 0.5, depth);
  vec3 n = ssao_unpack_plane_normal(own_plane.z);
  vec3 po = p - frame.camera_pos.xyz;
  float inv_sigma = 10.0 / ssao.shape.x;
  ivec2 at = own - tile_origin;
  float sum = 0.0, weights = 0.0, best = -1.0,
        best_ao = uintBitsToFloat(tile[at.y * side + at.x].w);
  for (int y = -reach; y <= reach; ++y)
    for (int x = -reach; x <= reach; ++x) {
      ivec2 q = own + ivec2(x, y);
      uvec4 v = tile[(at.y + y) * side + at.x + x];
      if (uintBitsToFloat(v.x) < 0.0) continue;
      vec3 nq = ssao_unpack_plane_normal(v.z);
      float delta = (dot(po, nq) - uintBitsToFloat(v.y)) * inv_sigma;
      float w = exp(-delta * delta) * pow(max(dot(n, nq), 0.0), 8.0);
      float a = uintBitsToFloat(v.w);
      if (r == 0) {
        if (q == own && w >= 0.5) {  // the pixel's own texel, on its surface
          best = 2.0;
          best_ao = a;
        } else if (w > best) {
          best = w;
          best_ao = a;
        }
        continue;
      }
      sum += w * a;
      weights += w;
    }
  imageStore(ao_out, pixel, vec4(r == 0 || weights <= 0.0 ? best_ao : sum / weights));
}
