// PRT display (S002 §5.5, docs/prt.md): E/π = Σ_i T_i L_i from the transfer points of the
// `prt` lighting input (inputs/prt.glsl, which includes this file after its bindings) and the
// sun's SH coefficients the `baked` add-on projects each frame. The
// lookups are `illum relight`'s (bake/prt_relight.cpp), so the two agree to the half-float
// rounding of the stored transfer: per vertex (the caller interpolates prt_point_relit of
// the triangle's vertices, or lets the rasterizer do it), per texel (bilinear over texel
// centres, clamped) and VQ (4 nearest taps at ±¼ texel, averaged).
#ifndef ILLUM_PRT_GLSL
#define ILLUM_PRT_GLSL

float prt_half(uint k) {
  vec2 pair = unpackHalf2x16(prt_points[k >> 1]);
  return (k & 1u) == 0u ? pair.x : pair.y;
}

// Σ_i T_i L_i (RGB) of one transfer point.
vec3 prt_point_relit(uint point) {
  uint k = point * uint(prt_input.size.z);
  vec3 sum = vec3(0.0);
  for (int i = 0; i < prt_input.info.y; ++i, k += 3u)
    sum += vec3(prt_half(k), prt_half(k + 1u), prt_half(k + 2u)) * prt_input.light[i].rgb;
  return sum;
}

uint prt_vq_index(uint texel) {
  uint word = prt_vq_indices[texel >> 1];
  return (texel & 1u) == 0u ? (word & 0xffffu) : (word >> 16);
}

// The texel or VQ lookup at uv1 (relit).
vec3 prt_atlas_relit(vec2 uv1) {
  ivec2 size = prt_input.size.xy;
  vec3 sum = vec3(0.0);
  if (prt_input.info.x == kPrtVq) {
    for (int k = 0; k < 4; ++k) {
      vec2 o = vec2((k & 1) != 0 ? 0.25 : -0.25, (k >> 1) != 0 ? 0.25 : -0.25);
      ivec2 t = clamp(ivec2(floor(uv1 * vec2(size) + o)), ivec2(0), size - 1);
      sum += 0.25 * prt_point_relit(prt_vq_index(uint(t.y * size.x + t.x)));
    }
    return sum;
  }
  vec2 p = uv1 * vec2(size) - 0.5;
  ivec2 p0 = ivec2(floor(p));
  vec2 a = p - vec2(p0);
  for (int k = 0; k < 4; ++k) {
    ivec2 t = clamp(p0 + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
    float w = ((k & 1) != 0 ? a.x : 1.0 - a.x) * ((k >> 1) != 0 ? a.y : 1.0 - a.y);
    sum += w * prt_point_relit(uint(t.y * size.x + t.x));
  }
  return sum;
}

#endif
