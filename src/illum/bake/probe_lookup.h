// CPU lookups in a baked probe grid (baked/probe_file.h).
//
// Lookup at a point p: the 8 probes of the grid cell around p (p clamped into the grid),
// each with its trilinear weight × its validity weight (0 for an invalid probe) × (with
// `occluders`) its visibility from p: a probe whose segment to p is blocked by geometry
// counts 0. The weights are renormalised to sum 1 over what remains, so invalid or hidden
// probes drop out without darkening the result; when nothing remains the lookup is black
// and says so (ProbeSample::weight = 0). The visibility test is what keeps light from
// leaking through a wall thinner than the probe spacing (docs/probes.md, leak test): the
// probes on the wall's other side are blocked and drop out.
#pragma once

#include <span>
#include <vector>

#include "illum/bake/probe_baker.h"
#include "illum/baked/probe_file.h"
#include "illum/trace/ray_tracer.h"

namespace illum::bake {

struct ProbeSample {
  float irradiance[kProbeCoefficients * 3] = {};  // interpolated E_i, [i][rgb]
  float cube[6 * 3] = {};                         // interpolated ambient cube, [face][rgb]
  // Σ of the trilinear × validity × visibility weights before renormalisation (0: no probe
  // around p is usable and the sample is black).
  float weight = 0.0f;
};

// `occluders`: a tracer of the set's static geometry, or nullptr for no visibility test.
ProbeSample lookup_probes(const baked::ProbeSet& set, const vec3& p,
                          const RayTracer* occluders = nullptr);
// E(n) at p from the interpolated coefficients (W/m²; ÷π for a white Lambertian's radiance).
Color lookup_irradiance(const baked::ProbeSet& set, const vec3& p, const vec3& n,
                        const RayTracer* occluders = nullptr);

// One ambient cube per dynamic instance at the centre of its world bounds (validity- and,
// with `occluders`, visibility-weighted lookups). The real-time renderer does its own lookup
// (realtime/probe_volume.h: per pixel, with a leak guard in place of visibility rays).
// Throws Error (check_probe_scene) when the set was baked for another scene.
struct InstanceCube {
  int instance = -1;
  Color cube[6];
  float weight = 0.0f;  // ProbeSample::weight (0: no usable probe, black)
};
std::vector<InstanceCube> dynamic_instance_cubes(const baked::ProbeSet& set, const Scene& scene,
                                                 const RayTracer* occluders = nullptr);

// The records as the real-time renderer reads them (realtime::ProbeVolume::probes, without
// this layer including it): per probe its 27 irradiance coefficients, then its weight.
inline constexpr int kProbeVolumeFloats = kProbeCoefficients * 3 + 1;
std::vector<float> probe_volume_data(std::span<const ProbeRecord> probes);
// The instances of `scene` marked dynamic (the ones the probes light), in scene order.
std::vector<int> dynamic_instances(const Scene& scene);

}  // namespace illum::bake
