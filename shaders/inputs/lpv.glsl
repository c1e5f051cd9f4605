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
  vec4 params;  // x: amplification, y: dampening
} lpv_input;
layout(set = kInputsSet, binding = kLpvInputBase + 1) uniform sampler3D lpv_accum;

vec4 lpv_sample(int c, vec3 p) {
  float n = float(lpv_input.info.x);
  vec3 t = clamp((p - lpv_input.lo.xyz) / lpv_input.lo.w, vec3(0.5), vec3(n - 0.5));
  return textureLod(lpv_accum, vec3((t.x + float(c) * n) / (3.0 * n), t.y / n, t.z / n), 0.0);
}

vec3 lpv_irradiance(vec3 p, vec3 n) {
  vec3 e;
  for (int c = 0; c < 3; ++c) {
    vec4 v = lpv_sample(c, p);
    e[c] = 0.886226925452758 * v.x - 1.0233267079464885 * dot(v.yzw, n);
  }
  return max(e, vec3(0.0)) / (lpv_input.lo.w * lpv_input.lo.w);
}

void input_lpv(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kLpvInput) || t.has_indirect) return;
  vec3 e = lpv_irradiance(s.p, s.n);
  // Derivative dampening against leaks through thin walls: light the normal sees is stronger
  // half a cell behind the surface than half a cell in front of it only where it comes
  // through the surface; the term is scaled down by that excess, relative, × dampening.
  float damp = 1.0;
  if (lpv_input.params.y > 0.0) {
    float h = 0.5 * lpv_input.lo.w;
    vec3 front = lpv_irradiance(s.p + h * s.n, s.n);
    vec3 behind = lpv_irradiance(s.p - h * s.n, s.n);
    float b = dot(behind, vec3(1.0)), f = dot(front, vec3(1.0));
    if (b > f) damp = clamp(1.0 - lpv_input.params.y * (b - f) / b, 0.0, 1.0);
  }
  t.indirect = s.albedo * e * (lpv_input.params.x * damp / kPi);
  t.has_indirect = true;
}

#endif
