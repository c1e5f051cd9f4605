#include "illum/bake/probe_lookup.h"

#include <cmath>

#include "illum/core/error.h"
#include "illum/core/trilinear_cell.h"
#include "illum/scene/instance_bounds.h"

namespace illum::bake {

ProbeSample lookup_probes(const baked::ProbeSet& set, const vec3& p, const RayTracer* occluders) {
  const ProbeGrid& grid = set.grid;
  if (grid.count() < 1 || size_t(grid.count()) != set.probes.size())
    throw Error(fmt::format("probe lookup: {} records for a {}×{}×{} grid", set.probes.size(),
                            grid.size.x, grid.size.y, grid.size.z));
  ProbeSample out;
  if (!is_finite(p)) return out;
  const glm::ivec3 n = grid.size;
  const TrilinearCell cell(n, grid.origin, vec3(grid.spacing), p);
  float weights[8];
  const ProbeRecord* records[8];
  float total = 0.0f;
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 c = cell.corner(k);
    const int x = c.x, y = c.y, z = c.z;
    const ProbeRecord& r =
        set.probes[(size_t(z) * size_t(n.y) + size_t(y)) * size_t(n.x) + size_t(x)];
    float w = cell.weight(k);
    w *= r.weight;
    if (w > 0.0f && occluders) {
      const vec3 d = grid.position(x, y, z) - p;
      const float distance = glm::length(d);
      // Stops just short of the probe, as shadow rays stop short of a light.
      if (distance > 0.0f &&
          occluders->occluded(Ray{p, d / distance, 0.0f, distance * (1.0f - 1e-4f)}))
        w = 0.0f;
    }
    weights[k] = w;
    records[k] = &r;
    total += w;
  }
  out.weight = total;
  if (!(total > 0.0f)) return out;
  for (int k = 0; k < 8; ++k) {
    if (weights[k] == 0.0f) continue;
    const float w = weights[k] / total;
    for (int i = 0; i < kProbeCoefficients * 3; ++i)
      out.irradiance[i] += w * records[k]->irradiance[i];
    for (int i = 0; i < 18; ++i) out.cube[i] += w * records[k]->cube[i];
  }
  return out;
}

Color lookup_irradiance(const baked::ProbeSet& set, const vec3& p, const vec3& n,
                        const RayTracer* occluders) {
  const ProbeSample s = lookup_probes(set, p, occluders);
  return irradiance_from_sh(s.irradiance, n);
}

std::vector<InstanceCube> dynamic_instance_cubes(const baked::ProbeSet& set, const Scene& scene,
                                                 const RayTracer* occluders) {
  baked::check_probe_scene(scene, set);
  std::vector<InstanceCube> out;
  for (const int i : dynamic_instances(scene)) {
    const Instance& inst = scene.instances[size_t(i)];
    const ProbeSample s = lookup_probes(set, instance_bounds(scene, inst).center(), occluders);
    InstanceCube cube;
    cube.instance = i;
    cube.weight = s.weight;
    for (int f = 0; f < 6; ++f)
      cube.cube[f] = Color(s.cube[3 * f], s.cube[3 * f + 1], s.cube[3 * f + 2]);
    out.push_back(cube);
  }
  return out;
}

std::vector<float> probe_volume_data(std::span<const ProbeRecord> probes) {
  std::vector<float> data;
  data.reserve(probes.size() * kProbeVolumeFloats);
  for (const ProbeRecord& r : probes) {
    data.insert(data.end(), std::begin(r.irradiance), std::end(r.irradiance));
    data.push_back(r.weight);
  }
  return data;
}

std::vector<int> dynamic_instances(const Scene& scene) {
  std::vector<int> out;
  for (size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].dynamic) out.push_back(int(i));
  return out;
}

}  // namespace illum::bake
