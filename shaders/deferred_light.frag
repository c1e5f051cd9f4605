#version 450
#include "lighting.glsl"
// One light over the G-buffer: position from depth, the same lighting as the forward path.
layout(set = 2, binding = 0) uniform sampler2D g_albedo;
layout(set = 2, binding = 1) uniform sampler2D g_normal;
layout(set = 2, binding = 2) uniform sampler2D g_geometry;
layout(set = 2, binding = 3) uniform sampler2D g_specular;
layout(set = 2, binding = 4) uniform sampler2D g_depth;
layout(location = 0) out vec4 out_color;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(g_depth, pixel, 0).r;
  if (depth >= 1.0) discard;
  vec2 ndc = (vec2(pixel) + 0.5) * frame.extent.zw * 2.0 - 1.0;
  vec4 h = frame.inv_view_proj * vec4(ndc, depth, 1.0);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  vec4 normal = texelFetch(g_normal, pixel, 0);
  vec4 geometry = texelFetch(g_geometry, pixel, 0);
  Surface s;
  s.p = h.xyz / h.w;
  s.n = normalize(normal.xyz);
  s.ng = normalize(geometry.xyz);
  s.albedo = albedo.rgb;
  s.specular = texelFetch(g_specular, pixel, 0).rgb;
  s.exponent = geometry.w;
  s.type = int(albedo.a * 4.0 + 0.5);
  s.emission = vec3(0.0);
  s.n_z = normal.w;
  s.uv1 = vec2(0.0);
  vec3 v = normalize(frame.camera_pos.xyz - s.p);
  vec3 radiance, l;
  if (!light_contribution(push.light_index, s, v, radiance, l)) discard;
  out_color = vec4(radiance * cube_shadow(push.light_index, s.p, s.ng, gl_FragCoord.xy), 1.0);
}
