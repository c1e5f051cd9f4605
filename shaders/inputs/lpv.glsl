// Lighting input `lpv` (techniques/lpv.cpp, docs/realtime-lpv.md): the light propagation
// volume's accumulated light, per cell and colour channel the L1 SH of its radiant intensity
// (c0, c) (lpv_common.glsl), in an atlas of three parts along x (R, G, B) and the cascades one
// after the other along z, sampled trilinearly with the coordinate clamped to each part's
// outer cell centres. Radiance is the intensity over the cell's cross-section s², and the
// irradiance of a surface with normal n gathers the light moving along −n:
// E(n) = (π·Y0·c0 − (2π/3)·√(3/4π)·c·n)/s² = (√π/2·c0 − √(π/3)·c·n)/s². A point takes the
// finest cascade holding it, whose cells near its border hold its light blended into the next
// coarser cascade's (lpv_resolve.comp), so the border leaves no seam. A fourth part holds the
// DC sum's gradient for the leak dampening.
// Must match LpvInputUniforms in techniques/lpv.cpp.
#ifndef ILLUM_INPUT_LPV_GLSL
#define ILLUM_INPUT_LPV_GLSL

layout(std140, set = kInputsSet, binding = kLpvInputBase) uniform LpvInput {
  vec4 lo[4];   // per cascade: xyz its min corner; w its cell size s (past the last: the last)
  vec4 slot;    // per cascade: the z of its part of the atlas, in texture coordinates
  ivec4 info;   // x: cells per axis; y: cascades
  vec4 params;  // x: amplification; y: dampening
} lpv_input;
layout(set = kInputsSet, binding = kLpvInputBase + 1) uniform sampler3D lpv_accum;

// Whether p lies inside the outermost cell centres of the cascade whose box is `box`.
bool lpv_holds(vec4 box, vec3 p) {
  vec3 t = (p - box.xyz) / box.w;
  float n = float(lpv_input.info.x);
  return min(t.x, min(t.y, t.z)) > 0.5 && max(t.x, max(t.y, t.z)) < n - 0.5;
}

vec3 lpv_irradiance(vec3 p, vec3 n) {
  // The finest cascade holding p (they nest), written out with constant indices and no loop:
  // a loop, an array indexed by a variable or a second cascade's fetches here made lavapipe's
  // (Mesa 22.3) compiler corrupt its heap now and then while building the visibility resolve.
  // The blend into the coarser cascade is in the atlas already (lpv_resolve.comp).
  vec4 box = lpv_input.lo[3];
  float slot = lpv_input.slot.w;
  if (lpv_holds(lpv_input.lo[2], p)) {
    box = lpv_input.lo[2];
    slot = lpv_input.slot.z;
  }
  if (lpv_holds(lpv_input.lo[1], p)) {
    box = lpv_input.lo[1];
    slot = lpv_input.slot.y;
  }
  if (lpv_holds(lpv_input.lo[0], p)) {
    box = lpv_input.lo[0];
    slot = lpv_input.slot.x;
  }
  float cells = float(lpv_input.info.x);
  vec3 t = clamp((p - box.xyz) / box.w, vec3(0.5), vec3(cells - 0.5)) / cells;
  t.z = slot + t.z / float(lpv_input.info.y);
  // The three channels written out: a loop storing e[c] crashed that compiler too.
  vec4 r = textureLod(lpv_accum, vec3(t.x * 0.25, t.yz), 0.0);
  vec4 g = textureLod(lpv_accum, vec3((t.x + 1.0) * 0.25, t.yz), 0.0);
  vec4 b = textureLod(lpv_accum, vec3((t.x + 2.0) * 0.25, t.yz), 0.0);
  vec3 e = 0.886226925452758 * vec3(r.x, g.x, b.x) -
           1.0233267079464885 * vec3(dot(r.yzw, n), dot(g.yzw, n), dot(b.yzw, n));
  // Leak dampening: light growing towards the back of the surface (derivative of the DC sum
  // along n below 0, per cell) came through it; scale by 1 + dampening·derivative/sum.
  vec4 d = textureLod(lpv_accum, vec3((t.x + 3.0) * 0.25, t.yz), 0.0);
  float damp = clamp(1.0 + lpv_input.params.y * min(dot(d.xyz, n), 0.0) / max(d.w, 1e-20), 0.0, 1.0);
  return max(e, vec3(0.0)) * (damp / (box.w * box.w));
}

void input_lpv(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kLpvInput) || t.has_indirect) return;
  vec3 e = lpv_irradiance(s.p, s.n);
  t.indirect = s.albedo * e * (lpv_input.params.x / kPi);
  t.has_indirect = true;
}

#endif
