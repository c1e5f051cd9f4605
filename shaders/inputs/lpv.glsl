// Lighting input `lpv` (techniques/lpv.cpp, docs/realtime-lpv.md): the light propagation
// volume's accumulated light, per cell and colour channel the L1 SH of its radiant intensity
// (c0, c) (lpv_common.glsl), in an atlas of three parts along x (R, G, B) sampled trilinearly
// with the coordinate clamped to each part's outer cell centres. Radiance is the intensity
// over the cell's cross-section s², and the irradiance of a surface with normal n gathers the
// light moving along −n: E(n) = (π·Y0·c0 − (2π/3)·√(3/4π)·c·n)/s² = (√π/2·c0 − √(π/3)·c·n)/s².
// Must match LpvUniforms' input part in techniques/lpv.cpp.
#ifndef ILLUM_INPUT_LPV_GLSL
#define ILLUM_INPUT_LPV_GLSL

layout(std140, set = kInputsSet, binding = kLpvInputBase) uniform LpvInput {
  vec4 lo;      // xyz: the volume's min corner; w: the cell size s
  ivec4 info;   // x: cells per axis
  vec4 params;  // x: amplification
} lpv_input;
layout(set = kInputsSet, binding = kLpvInputBase + 1) uniform sampler3D lpv_accum;

vec4 lpv_sample(int c, vec3 p) {
  float n = float(lpv_input.info.x);
  vec3 t = clamp((p - lpv_input.lo.xyz) / lpv_input.lo.w, vec3(0.5), vec3(n - 0.5));
  return textureLod(lpv_accum, vec3((t.x + float(c) * n) / (3.0 * n), t.y / n, t.z / n), 0.0);
}

vec3 lpv_irradiance(vec3 p, vec3 n) {
  // The three channels written out: a loop storing e[c] crashed lavapipe's (Mesa 22.3)
  // compiler now and then (heap corruption while building the visibility resolve).
  vec4 r = lpv_sample(0, p), g = lpv_sample(1, p), b = lpv_sample(2, p);
  vec3 e = 0.886226925452758 * vec3(r.x, g.x, b.x) -
           1.0233267079464885 * vec3(dot(r.yzw, n), dot(g.yzw, n), dot(b.yzw, n));
  return max(e, vec3(0.0)) / (lpv_input.lo.w * lpv_input.lo.w);
}

void input_lpv(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kLpvInput) || t.has_indirect) return;
  vec3 e = lpv_irradiance(s.p, s.n);
  t.indirect = s.albedo * e * (lpv_input.params.x / kPi);
  t.has_indirect = true;
}

#endif
