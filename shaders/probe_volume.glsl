// Per-pixel irradiance of the probe volume for dynamic objects (the CPU
// mirror, operation for operation, is realtime/probe_volume.cpp probe_volume_irradiance, and
// tests/realtime/probe_volume_test.cpp holds the two together pixel by pixel).
//
// The 8 probes of the grid cell around p (p clamped into the grid) weighted by trilinear
// weight × validity × leak guard, renormalised; E(n) = Σ_i E_i Y_i(n) of the blend (the bake
// stored irradiance coefficients, Ramamoorthi–Hanrahan's Λ_l applied). Leak guard: DDGI's
// smooth back-face weight ((1 + cos θ)/2)² + 0.2, θ between the geometric normal and the
// direction to the probe (docs/probes.md says why).
// The volume's bindings are the `probes` lighting input's (inputs/probes.glsl includes this
// file after them).
#ifndef ILLUM_PROBE_VOLUME_GLSL
#define ILLUM_PROBE_VOLUME_GLSL
#include "sh.glsl"

const int kProbeFloats = 28;               // realtime/probe_volume.h
const float kProbeLeakGuardFloor = 0.2;

// E(n) in W/m² at p (unit n: shading normal, ng: geometric normal); black when no probe of
// the cell is usable. Not clamped: SH-L2 can ring below 0, the caller clamps.
vec3 probe_volume_irradiance(vec3 p, vec3 n, vec3 ng) {
  ivec3 size = probes_input.size.xyz;
  vec3 origin = probes_input.origin.xyz, spacing = probes_input.spacing.xyz;
  vec3 g = clamp((p - origin) / spacing, vec3(0.0), vec3(size - 1));
  ivec3 i0 = min(ivec3(floor(g)), size - 1);
  ivec3 i1 = min(i0 + 1, size - 1);
  vec3 t = g - vec3(i0);
  float y[9];
  sh_basis_l2(n, y);
  vec3 sum = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < 8; ++k) {
    bvec3 hi = bvec3((k & 1) != 0, (k & 2) != 0, (k & 4) != 0);
    ivec3 c = ivec3(hi.x ? i1.x : i0.x, hi.y ? i1.y : i0.y, hi.z ? i1.z : i0.z);
    vec3 f = vec3(hi.x ? t.x : 1.0 - t.x, hi.y ? t.y : 1.0 - t.y, hi.z ? t.z : 1.0 - t.z);
    int base = ((c.z * size.y + c.y) * size.x + c.x) * kProbeFloats;
    float w = f.x * f.y * f.z * probe_data[base + kProbeFloats - 1];
    vec3 to_probe = origin + spacing * vec3(c) - p;
    float facing = dot(to_probe, ng) * inversesqrt(max(dot(to_probe, to_probe), 1e-12));
    float wrap = 0.5 * facing + 0.5;
    w *= wrap * wrap + kProbeLeakGuardFloor;
    if (!(w > 0.0)) continue;
    vec3 e = vec3(0.0);
    for (int i = 0; i < 9; ++i)
      e += y[i] * vec3(probe_data[base + 3 * i], probe_data[base + 3 * i + 1],
                       probe_data[base + 3 * i + 2]);
    sum += w * e;
    total += w;
  }
  return total > 0.0 ? sum / total : vec3(0.0);
}

#endif
