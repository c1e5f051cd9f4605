// CPU lookups in a baked probe grid (probe_file.h) and its conversion for the real-time
// renderer's ambient cubes.
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

#include <vector>

#include "illum/bake/probe_file.h"
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
ProbeSample lookup_probes(const ProbeSet& set, const vec3& p, const RayTracer* occluders = nullptr);
// E(n) at p from the interpolated coefficients (W/m²; ÷π for a white Lambertian's radiance).
Color lookup_irradiance(const ProbeSet& set, const vec3& p, const vec3& n,
                        const RayTracer* occluders = nullptr);

// The real-time renderer's input for the instances of `scene` marked dynamic
// (realtime::AmbientCubeGrid in realtime/baked_data.h has the same fields: copy them over).
// The renderer interpolates the grid trilinearly at each instance's centre without validity
// weights, so invalid probes are filled here with the mean of their valid neighbours
// (26-neighbourhood, repeated outward until every probe is filled; all black if none is
// valid). Throws Error (check_probe_scene) when the set was baked for another scene.
struct ProbeCubeGrid {
  glm::ivec3 size{0};
  vec3 origin{0.0f}, spacing{1.0f};
  std::vector<Color> cubes;    // 6 per probe, faces +x, −x, +y, −y, +z, −z, E/π
  std::vector<int> instances;  // the dynamic instances of `scene`
};
ProbeCubeGrid probe_cube_grid(const ProbeSet& set, const Scene& scene);

// Exact lookups instead (validity- and, with `occluders`, visibility-weighted): one cube per
// dynamic instance at the centre of its world bounds, for a renderer that takes cubes per
// draw (realtime BakedData::cubes, 6 per probed draw).
struct InstanceCube {
  int instance = -1;
  Color cube[6];
  float weight = 0.0f;  // ProbeSample::weight (0: no usable probe, black)
};
std::vector<InstanceCube> dynamic_instance_cubes(const ProbeSet& set, const Scene& scene,
                                                 const RayTracer* occluders = nullptr);

}  // namespace illum::bake
