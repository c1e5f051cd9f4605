// The irradiance volume the `baked` add-on reads per pixel to light instances marked
// "dynamic": true (docs/probes.md "In the real-time renderer"), and the CPU
// mirror of that lookup, operation for operation as shaders/probe_volume.glsl does it, for
// the tests and the per-instance ambient-cube fallback.
//
// Lookup at a surface point p with shading normal n and geometric normal ng: the 8 probes of
// the grid cell around p (p clamped into the grid), each weighted by
//   trilinear weight × validity weight × leak guard,
// leak guard = ((1 + cos θ)/2)² + kProbeLeakGuardFloor, θ the angle between ng and the
// direction from p to the probe (DDGI's smooth back-face weight, Majercik et al. 2019): a probe
// in front of the surface counts 1.2, one beside it 0.45, one straight behind it 0.2. The
// weights are renormalised over the 8, so invalid probes (validity 0) drop out without
// darkening; when none is usable the result is black. E(n) = Σ_i E_i Y_i(n) of the blended
// SH-L2 coefficients (core/sh.h; the bake already applied Ramamoorthi–Hanrahan's Λ_l).
#pragma once

#include <vector>

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

inline constexpr int kProbeShCoefficients = 9;                     // SH-L2
inline constexpr int kProbeFloats = 3 * kProbeShCoefficients + 1;  // per probe, with validity
// The leak guard's floor: a probe straight behind the surface keeps 0.2/1.2 = 1/6 of the
// weight of one straight in front. Never 0, so the result stays continuous over the surface
// and a point whose only valid probes are behind it is still lit (by them).
inline constexpr float kProbeLeakGuardFloor = 0.2f;

struct ProbeVolume {
  glm::ivec3 size{0};
  vec3 origin{0.0f}, spacing{1.0f};
  // kProbeFloats per probe, probe (x, y, z) at origin + spacing·(x, y, z) in record
  // (z·ny + y)·nx + x: 27 irradiance coefficients E_i [i][rgb] (W/m², world frame, pole +z),
  // then the validity weight in [0, 1] (the bake writes 0 or 1).
  std::vector<float> probes;
  std::vector<int> instances;  // the scene instances it lights (the ones marked dynamic)
  bool empty() const { return instances.empty(); }
  size_t count() const;  // nx·ny·nz
};

// Throws Error (one line) for a grid size < 1 on an axis, a spacing not positive and finite,
// a value count other than kProbeFloats per probe, a non-finite value, a validity weight
// outside [0, 1], or an instance that `scene` does not have.
void check_probe_volume(const ProbeVolume& volume, const Scene& scene);

struct ProbeVolumeSample {
  Color irradiance{0.0f};  // E(n), W/m² (may be negative where SH-L2 rings; the shader clamps)
  float weight = 0.0f;     // Σ of the 8 weights before renormalising (0: black)
};
// The shader's lookup on the CPU (float, same order of operations). n, ng: unit.
ProbeVolumeSample probe_volume_irradiance(const ProbeVolume& volume, const vec3& p, const vec3& n,
                                          const vec3& ng);

}  // namespace illum::realtime
