#version 450
// Used by tests/gpu/sh_glsl_test.cpp: every function of sh.glsl for the directions in
// data (record of 20 floats: in 0..2 the direction; out 4..12 sh_basis_l2, 13..16
// sh_basis_l1, 17..19 sh_irradiance_over_pi_l1 of the pushed RGB coefficients).
#include "sh.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Data { float data[]; };
layout(push_constant) uniform Push { vec4 c[4]; uint count; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  uint r = i * 20u;
  vec3 d = vec3(data[r], data[r + 1u], data[r + 2u]);
  float y[9];
  sh_basis_l2(d, y);
  for (uint k = 0u; k < 9u; ++k) data[r + 4u + k] = y[k];
  vec4 l1 = sh_basis_l1(d);
  for (uint k = 0u; k < 4u; ++k) data[r + 13u + k] = l1[k];
  vec3 e = sh_irradiance_over_pi_l1(c[0].rgb, c[1].rgb, c[2].rgb, c[3].rgb, d);
  data[r + 17u] = e.r;
  data[r + 18u] = e.g;
  data[r + 19u] = e.b;
}
