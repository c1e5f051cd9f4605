// Lighting input `lightmap` (techniques/baked.cpp): the light-map at uv1 (× the baked
// intensity). Plain maps are scaled by N_z (S002 §4.1); RNM (S003 ch. 7) blends its three
// tangent-space basis maps with weights max(n·b_i, 0)² normalised; SH-L1 maps hold the
// tangent-space radiance SH (sh.glsl, the normal as the pole) and give
// E(n)/π = c0·Y00 + (2/3)·Σ c1m·Y1m(n); dominant maps hold ambient A, directional colour C
// and the tangent-space direction d: A + C·max(0, n·d) (bake/lightmap_basis.h; exact E/π on
// the baked normal, so a surface without a normal map shows what the plain map shows).
// Must match LightmapInputUniforms in realtime/gpu_types.h.
#ifndef ILLUM_INPUT_LIGHTMAP_GLSL
#define ILLUM_INPUT_LIGHTMAP_GLSL
#include "sh.glsl"

layout(std140, set = kInputsSet, binding = kLightmapInputBase) uniform LightmapInput {
  ivec4 info;      // x: kind (1 plain, 2 RNM, 3 SH-L1, 4 dominant)
  vec4 intensity;  // x: multiplies the map
} lightmap_input;
// Layers: 1 = plain, 3 = RNM basis 0..2, 4 = SH-L1 coefficients 0..3, 3 = dominant:
// ambient, directional colour, direction (tangent space).
layout(set = kInputsSet, binding = kLightmapInputBase + 1) uniform sampler2DArray lightmap;

// Sampling hook: fragment shaders sample with the implicit LOD of their quads; a compute
// pass (visibility_resolve.comp) defines this first to pass explicit gradients.
#ifndef SAMPLE_LIGHTMAP
#define SAMPLE_LIGHTMAP(uvw) texture(lightmap, uvw)
#endif

vec3 lightmap_irradiance(Surface s, int kind) {
  float k = lightmap_input.intensity.x;
  vec3 uv = vec3(s.uv1, 0.0);
  if (kind == 1) return s.albedo * k * SAMPLE_LIGHTMAP(uv).rgb * s.n_z;
  vec3 n = s.n_ts;
  if (kind == 2) {
    const vec3 b0 = vec3(0.816496581, 0.0, 0.577350269);
    const vec3 b1 = vec3(-0.408248290, 0.707106781, 0.577350269);
    const vec3 b2 = vec3(-0.408248290, -0.707106781, 0.577350269);
    vec3 w = max(vec3(dot(n, b0), dot(n, b1), dot(n, b2)), 0.0);
    w *= w;
    w /= max(w.x + w.y + w.z, 1e-6);
    vec3 l = w.x * SAMPLE_LIGHTMAP(vec3(s.uv1, 0.0)).rgb + w.y * SAMPLE_LIGHTMAP(vec3(s.uv1, 1.0)).rgb +
             w.z * SAMPLE_LIGHTMAP(vec3(s.uv1, 2.0)).rgb;
    return s.albedo * k * l;
  }
  if (kind == 4) {
    vec3 a = SAMPLE_LIGHTMAP(vec3(s.uv1, 0.0)).rgb;
    vec3 c = SAMPLE_LIGHTMAP(vec3(s.uv1, 1.0)).rgb;
    // Not renormalised: between texels of different directions the blend is shorter, a
    // wider lobe, and on the baked normal the result stays the blend of the texels' exact
    // E/π but for −Cov(C, d_z) over the filter's weights (renormalising can push d_z to 1).
    vec3 d = SAMPLE_LIGHTMAP(vec3(s.uv1, 2.0)).rgb;
    return s.albedo * k * max(a + c * max(dot(n, d), 0.0), 0.0);
  }
  vec3 c0 = SAMPLE_LIGHTMAP(vec3(s.uv1, 0.0)).rgb;
  vec3 c1 = SAMPLE_LIGHTMAP(vec3(s.uv1, 1.0)).rgb;  // y
  vec3 c2 = SAMPLE_LIGHTMAP(vec3(s.uv1, 2.0)).rgb;  // z
  vec3 c3 = SAMPLE_LIGHTMAP(vec3(s.uv1, 3.0)).rgb;  // x
  vec3 e = sh_irradiance_over_pi_l1(c0, c1, c2, c3, n);
  return s.albedo * k * max(e, 0.0);
}

void input_lightmap(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kLightmapInput) || t.has_indirect) return;
  int kind = lightmap_input.info.x;
  if (kind == 0) return;
  t.indirect = lightmap_irradiance(s, kind);
  t.has_indirect = true;
}

#endif
