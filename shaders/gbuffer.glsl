// The compact G-buffer (set 2) shared by the deferred lighting passes: albedo + Phong
// exponent (RGBA16F: 8 bits would cost dark albedo channels several percent), both normals
// octahedral in one RGBA16F, specular + material type (RGBA8); position from depth.
#ifndef ILLUM_GBUFFER_GLSL
#define ILLUM_GBUFFER_GLSL
#include "lighting.glsl"

layout(set = 2, binding = 0) uniform sampler2D g_albedo;
layout(set = 2, binding = 1) uniform sampler2D g_normal;
layout(set = 2, binding = 2) uniform sampler2D g_specular;
layout(set = 2, binding = 3) uniform sampler2D g_depth;

Surface gbuffer_surface(ivec2 pixel, float depth) {
  vec2 ndc = (vec2(pixel) + 0.5) * views[push.view].extent.zw * 2.0 - 1.0;
  vec4 h = views[push.view].inv_view_proj * vec4(ndc, depth, 1.0);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  vec4 normals = texelFetch(g_normal, pixel, 0);
  vec4 specular = texelFetch(g_specular, pixel, 0);
  Surface s;
  s.p = h.xyz / h.w;
  s.n = oct_decode(normals.xy);
  s.ng = oct_decode(normals.zw);
  s.albedo = albedo.rgb;
  s.specular = specular.rgb;
  s.exponent = albedo.a;
  s.type = int(specular.a * 255.0 + 0.5);
  s.emission = vec3(0.0);  // emission and ambient were written by the G-buffer pass
  s.n_z = 1.0;
  s.n_ts = vec3(0.0, 0.0, 1.0);
  s.uv1 = vec2(0.0);
  s.prt_vertex = vec3(0.0);
  return s;
}

#endif
