#version 450
// SSAO normals for pipelines without a G-buffer (forward): from the depth buffer alone, the
// cross product of the horizontal and vertical position differences, each taken toward the
// neighbour whose depth is closer to this pixel's (so a silhouette next to the pixel does not
// bend it), turned toward the camera. Exact for planar surfaces; written in the G-buffer's
// octahedral layout (xy and zw both this normal).
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, rgba16f) uniform writeonly image2D normals_out;

vec3 neighbour(ivec2 pixel, ivec2 step, vec3 p, float depth, out bool ok) {
  ivec2 size = ivec2(frame.extent.xy);
  ivec2 a = clamp(pixel + step, ivec2(0), size - 1), b = clamp(pixel - step, ivec2(0), size - 1);
  float da = texelFetch(ssao_depth, a, 0).r, db = texelFetch(ssao_depth, b, 0).r;
  bool use_a = a != pixel && da < 1.0 && (b == pixel || db >= 1.0 || abs(da - depth) <= abs(db - depth));
  ok = use_a || (b != pixel && db < 1.0);
  if (use_a) return ssao_position(vec2(a) + 0.5, da) - p;
  return p - ssao_position(vec2(b) + 0.5, db);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  vec3 n = vec3(0.0, 0.0, 1.0);
  if (depth < 1.0) {
    vec3 p = ssao_position(vec2(pixel) + 0.5, depth);
    bool okx, oky;
    vec3 dx = neighbour(pixel, ivec2(1, 0), p, depth, okx);
    vec3 dy = neighbour(pixel, ivec2(0, 1), p, depth, oky);
    vec3 c = cross(dx, dy);
    if (okx && oky && dot(c, c) > 0.0) {
      n = normalize(c);
      if (dot(n, frame.camera_pos.xyz - p) < 0.0) n = -n;
    } else {
      n = normalize(frame.camera_pos.xyz - p);
    }
  }
  vec2 e = oct_encode(n);
  imageStore(normals_out, pixel, vec4(e, e));
}
