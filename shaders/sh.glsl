// Real spherical harmonics of bands 0–2 for the shaders: the constants and evaluation of
// src/illum/core/sh.h (convention there: orthonormal, no Condon–Shortley phase, index
// l(l+1)+m, z the polar axis of the frame the direction is written in), and the clamped-
// cosine factors Λ_l of Ramamoorthi & Hanrahan. Kept identical to core/sh.h by
// tests/gpu/sh_glsl_test.cpp, which runs every function here on the GPU against the C++
// evaluation, and tests/core/sh_test.cpp, which finds any SH constant spelt out elsewhere.
#ifndef ILLUM_SH_GLSL
#define ILLUM_SH_GLSL

const float kShY00 = 0.28209479177387814;   // 1/(2√π)
const float kShY1 = 0.48860251190291992;    // √(3/(4π)): (Y1−1, Y10, Y11) = kShY1·(y, z, x)
const float kShY2xy = 1.0925484305920792;   // √(15/(4π)): Y2−2 = ·xy, Y2−1 = ·yz, Y21 = ·xz
const float kShY20 = 0.31539156525252005;   // √(5/(16π)): Y20 = ·(3z² − 1)
const float kShY22 = 0.54627421529603959;   // √(15/(16π)): Y22 = ·(x² − y²)
// Clamped cosine max(n·ω, 0): irradiance E_lm = Λ_l·L_lm (Λ_0 = π, Λ_1 = 2π/3, Λ_2 = π/4).
const float kShCosine0 = 3.1415926535897932;
const float kShCosine1 = 2.0943951023931955;
const float kShCosine2 = 0.78539816339744831;
const float kShInvPi = 0.31830988618379067;

// (Y00, Y1−1, Y10, Y11) of a unit direction.
vec4 sh_basis_l1(vec3 d) { return vec4(kShY00, kShY1 * d.y, kShY1 * d.z, kShY1 * d.x); }

// Y_0 … Y_8 of a unit direction.
void sh_basis_l2(vec3 d, out float y[9]) {
  y[0] = kShY00;
  y[1] = kShY1 * d.y;
  y[2] = kShY1 * d.z;
  y[3] = kShY1 * d.x;
  y[4] = kShY2xy * d.x * d.y;
  y[5] = kShY2xy * d.y * d.z;
  y[6] = kShY20 * (3.0 * d.z * d.z - 1.0);
  y[7] = kShY2xy * d.x * d.z;
  y[8] = kShY22 * (d.x * d.x - d.y * d.y);
}

// E(n)/π from RGB radiance SH-L1 coefficients c0..c3 (order Y00, Y1−1, Y10, Y11).
vec3 sh_irradiance_over_pi_l1(vec3 c0, vec3 c1, vec3 c2, vec3 c3, vec3 n) {
  vec4 y = sh_basis_l1(n);
  return kShCosine0 * kShInvPi * y.x * c0 +
         kShCosine1 * kShInvPi * (y.y * c1 + y.z * c2 + y.w * c3);
}

#endif
