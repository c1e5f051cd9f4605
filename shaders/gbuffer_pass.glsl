#ifndef ILLUM_GBUFFER_PASS_GLSL
#define ILLUM_GBUFFER_PASS_GLSL
// The G-buffer pass's fragment shader (gbuffer.frag, gbuffer_indirect.frag). Compact G-buffer
// (see gbuffer.glsl): the material inputs of the lighting pass, plus emission + ambient
// written straight into the HDR target (the lighting pass adds to it). The pass runs before
// the screen-space phase, so it gathers the surface lighting inputs only; while a
// screen-space input is active (SSAO), gbuffer_indirect.frag also writes the indirect term
// and the occlusion it took into "gbuffer.indirect", and deferred_inputs.comp applies the
// screen-space occlusion over the HDR target.
#define LIGHTING_INPUTS_SURFACE_ONLY
#include "lighting.glsl"
layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec3 in_prt;

layout(location = 0) out vec4 out_albedo;    // rgb albedo, a: Phong exponent (fp16)
layout(location = 1) out vec4 out_normal;    // octahedral shading normal, geometric normal
layout(location = 2) out vec4 out_specular;  // rgb ks, a: material type / 255
layout(location = 3) out vec4 out_hdr;       // emission + ambient
#ifdef GBUFFER_INDIRECT
// rgb: the indirect term before occlusion; a: the occlusion it took, −1 where it holds its
// own visibility (PRT: no occlusion applies)
layout(location = 4) out vec4 out_indirect;
#endif

void main() {
  vec3 v = normalize(views[push.view].camera_pos.xyz - in_world);
  vec3 n = normalize(in_normal);
  Surface s = load_surface(push.material, in_world, n, in_tangent, in_uv, dot(n, v) >= 0.0);
  s.prt_vertex = in_prt;
  out_albedo = vec4(s.albedo, s.exponent);
  out_normal = vec4(oct_encode(s.n), oct_encode(s.ng));
  out_specular = vec4(s.specular, float(s.type) / 255.0);
#ifdef GBUFFER_INDIRECT
  LightingTerms t = gather_lighting_inputs(s, push.draw, gl_FragCoord.xy);
  vec3 indirect = ambient_indirect(s, t);
  out_hdr = vec4(s.emission + (indirect * indirect_occlusion(t) + t.specular + t.extra), 1.0);
  out_indirect = vec4(indirect, t.has_indirect && t.indirect_has_visibility ? -1.0 : t.occlusion);
#else
  out_hdr = vec4(s.emission + ambient_term(s, push.draw, gl_FragCoord.xy), 1.0);
#endif
}

#endif
