#include "illum/bake/probe_lookup.h"

#include <cmath>

#include "illum/core/error.h"

namespace illum::bake {

ProbeSample lookup_probes(const ProbeSet& set, const vec3& p, const RayTracer* occluders) {
  const ProbeGrid& grid = set.grid;
  if (grid.count() < 1 || size_t(grid.count()) != set.probes.size())
    throw Error(fmt::format("probe lookup: {} records for a {}×{}×{} grid", set.probes.size(),
                            grid.size.x, grid.size.y, grid.size.z));
  ProbeSample out;
  if (!is_finite(p)) return out;
  const glm::ivec3 n = grid.size;
  const vec3 g = glm::clamp((p - grid.origin) / grid.spacing, vec3(0.0f), vec3(n - 1));
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(g)), n - 1);
  const glm::ivec3 i1 = glm::min(i0 + 1, n - 1);
  const vec3 t = g - vec3(i0);
  float weights[8];
  const ProbeRecord* records[8];
  float total = 0.0f;
  for (int k = 0; k < 8; ++k) {
    const int x = k & 1 ? i1.x : i0.x, y = k & 2 ? i1.y : i0.y, z = k & 4 ? i1.z : i0.z;
    const ProbeRecord& r =
        set.probes[(size_t(z) * size_t(n.y) + size_t(y)) * size_t(n.x) + size_t(x)];
    float w = (k & 1 ? t.x : 1 - t.x) * (k & 2 ? t.y : 1 - t.y) * (k & 4 ? t.z : 1 - t.z);
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

Color lookup_irradiance(const ProbeSet& set, const vec3& p, const vec3& n,
                        const RayTracer* occluders) {
  const ProbeSample s = lookup_probes(set, p, occluders);
  return irradiance_from_sh(s.irradiance, n);
}

ProbeCubeGrid probe_cube_grid(const ProbeSet& set, const Scene& scene) {
  check_probe_scene(scene, set);
  const ProbeGrid& grid = set.grid;
  const glm::ivec3 n = grid.size;
  ProbeCubeGrid out;
  out.size = n;
  out.origin = grid.origin;
  out.spacing = vec3(grid.spacing);
  const size_t count = set.probes.size();
  out.cubes.assign(count * 6, Color(0.0f));
  std::vector<uint8_t> filled(count, 0);
  for (size_t i = 0; i < count; ++i) {
    if (set.probes[i].weight == 0.0f) continue;
    for (int f = 0; f < 6; ++f)
      out.cubes[i * 6 + size_t(f)] = Color(set.probes[i].cube[3 * f], set.probes[i].cube[3 * f + 1],
                                           set.probes[i].cube[3 * f + 2]);
    filled[i] = 1;
  }
  // Fill invalid probes ring by ring from the valid ones (each pass reads only probes filled
  // before it, so the result does not depend on the order within a pass).
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<uint8_t> next = filled;
    for (int z = 0; z < n.z; ++z)
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x) {
          const size_t i = (size_t(z) * size_t(n.y) + size_t(y)) * size_t(n.x) + size_t(x);
          if (filled[i]) continue;
          Color sum[6] = {};
          int used = 0;
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy, zz = z + dz;
                if (xx < 0 || yy < 0 || zz < 0 || xx >= n.x || yy >= n.y || zz >= n.z) continue;
                const size_t j = (size_t(zz) * size_t(n.y) + size_t(yy)) * size_t(n.x) + size_t(xx);
                if (!filled[j]) continue;
                for (int f = 0; f < 6; ++f) sum[f] += out.cubes[j * 6 + size_t(f)];
                ++used;
              }
          if (used == 0) continue;
          for (int f = 0; f < 6; ++f) out.cubes[i * 6 + size_t(f)] = sum[f] / float(used);
          next[i] = 1;
          changed = true;
        }
    filled = std::move(next);
  }
  for (size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].dynamic) out.instances.push_back(int(i));
  return out;
}

std::vector<InstanceCube> dynamic_instance_cubes(const ProbeSet& set, const Scene& scene,
                                                 const RayTracer* occluders) {
  check_probe_scene(scene, set);
  std::vector<InstanceCube> out;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (!inst.dynamic) continue;
    Bounds3 b;
    for (const vec3& p : scene.meshes[size_t(inst.mesh)].positions)
      b.extend(vec3(inst.transform * vec4(p, 1.0f)));
    const ProbeSample s = lookup_probes(set, b.center(), occluders);
    InstanceCube cube;
    cube.instance = int(i);
    cube.weight = s.weight;
    for (int f = 0; f < 6; ++f)
      cube.cube[f] = Color(s.cube[3 * f], s.cube[3 * f + 1], s.cube[3 * f + 2]);
    out.push_back(cube);
  }
  return out;
}

}  // namespace illum::bake
