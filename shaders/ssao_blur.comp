#version 450
// Depth-aware blur of the raw SSAO: a (2r+1)² box over pixels on the same surface — a
// neighbour counts with weight exp(−(Δ/σ)²)·max(n·n_i, 0)⁸, Δ its distance from this pixel's
// tangent plane and σ = R/10 — so occlusion does not bleed across silhouettes or creases.
// r = 0 copies.
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, r32f) uniform writeonly image2D ao_out;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.extent.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  float ao = texelFetch(ssao_source, pixel, 0).r;
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  int r = ssao.info.y;
  if (r == 0 || depth >= 1.0) {
    imageStore(ao_out, pixel, vec4(ao));
    return;
  }
  vec3 p = ssao_position(vec2(pixel) + 0.5, depth);
  vec3 n = ssao_geometric_normal(pixel);
  float sigma = 0.1 * ssao.shape.x;
  float sum = 0.0, weights = 0.0;
  for (int y = -r; y <= r; ++y)
    for (int x = -r; x <= r; ++x) {
      ivec2 q = pixel + ivec2(x, y);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      float dq = texelFetch(ssao_depth, q, 0).r;
      if (dq >= 1.0) continue;
      float delta = dot(n, ssao_position(vec2(q) + 0.5, dq) - p) / sigma;
      float w = exp(-delta * delta) * pow(max(dot(n, ssao_geometric_normal(q)), 0.0), 8.0);
      sum += w * texelFetch(ssao_source, q, 0).r;
      weights += w;
    }
  imageStore(ao_out, pixel, vec4(weights > 0.0 ? sum / weights : ao));
}
