#include "illum/realtime/probe_volume.h"

#include <cmath>
#include <span>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/sh.h"
#include "illum/core/trilinear_cell.h"
#include "illum/realtime/baked_data.h"
#include "illum/scene/instance_bounds.h"

namespace illum::realtime {

size_t ProbeVolume::count() const {
  if (size.x < 1 || size.y < 1 || size.z < 1) return 0;
  return static_cast<size_t>(size.x) * static_cast<size_t>(size.y) * static_cast<size_t>(size.z);
}

void check_probe_volume(const ProbeVolume& volume, const Scene& scene) {
  const glm::ivec3 n = volume.size;
  if (volume.count() == 0)
    throw Error(fmt::format("probe volume: a {}×{}×{} grid has no probes", n.x, n.y, n.z));
  if (!is_finite(volume.origin) || !is_finite(volume.spacing) ||
      !glm::all(glm::greaterThan(volume.spacing, vec3(0.0f))))
    throw Error(fmt::format("probe volume: spacing ({}, {}, {}) must be positive and finite",
                            volume.spacing.x, volume.spacing.y, volume.spacing.z));
  if (volume.probes.size() != volume.count() * kProbeFloats)
    throw Error(fmt::format("probe volume: {} values for a {}×{}×{} grid (need {} per probe)",
                            volume.probes.size(), n.x, n.y, n.z, kProbeFloats));
  for (size_t i = 0; i < volume.probes.size(); ++i) {
    const float v = volume.probes[i];
    const bool validity = i % kProbeFloats == kProbeFloats - 1;
    if (!std::isfinite(v) || (validity && (v < 0.0f || v > 1.0f)))
      throw Error(fmt::format("probe volume: probe {} holds {} {}", i / kProbeFloats,
                              validity ? "validity weight" : "value", v));
  }
  for (int inst : volume.instances)
    if (inst < 0 || static_cast<size_t>(inst) >= scene.instances.size())
      throw Error(fmt::format("probe volume: instance {} does not exist", inst));
}

ProbeVolumeSample probe_volume_irradiance(const ProbeVolume& volume, const vec3& p, const vec3& n,
                                          const vec3& ng) {
  // shaders/probe_volume.glsl, line for line.
  const glm::ivec3 size = volume.size;
  const TrilinearCell cell(size, volume.origin, volume.spacing, p);
  float y[kProbeShCoefficients];
  sh::evaluate<float>(3, n, std::span<float>(y, kProbeShCoefficients));
  ProbeVolumeSample out;
  Color sum(0.0f);
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 c = cell.corner(k);
    const size_t base =
        ((static_cast<size_t>(c.z) * static_cast<size_t>(size.y) + static_cast<size_t>(c.y)) *
             static_cast<size_t>(size.x) +
         static_cast<size_t>(c.x)) *
        kProbeFloats;
    const float* probe = volume.probes.data() + base;
    float w = cell.weight(k) * probe[kProbeFloats - 1];
    const vec3 to_probe = volume.origin + volume.spacing * vec3(c) - p;
    const float facing =
        glm::dot(to_probe, ng) / std::sqrt(std::max(glm::dot(to_probe, to_probe), 1e-12f));
    const float wrap = 0.5f * facing + 0.5f;
    w *= wrap * wrap + kProbeLeakGuardFloor;
    if (!(w > 0.0f)) continue;
    Color e(0.0f);
    for (int i = 0; i < kProbeShCoefficients; ++i)
      e += y[i] * Color(probe[3 * i], probe[3 * i + 1], probe[3 * i + 2]);
    sum += w * e;
    out.weight += w;
  }
  if (out.weight > 0.0f) out.irradiance = sum / out.weight;
  return out;
}

void probe_instance_cubes(const ProbeVolume& volume, const Scene& scene,
                          const std::vector<int>& draw_instances, BakedData* out) {
  check_probe_volume(volume, scene);
  static const vec3 kAxes[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  std::vector<vec4> cubes;
  std::vector<int> draw_cube(draw_instances.size(), 0);
  for (int inst : volume.instances) {
    const Instance& in = scene.instances[static_cast<size_t>(inst)];
    const vec3 centre = instance_bounds(scene, in).center();
    const int cube = static_cast<int>(cubes.size() / 6);
    for (const vec3& axis : kAxes) {
      const Color e = probe_volume_irradiance(volume, centre, axis, axis).irradiance;
      cubes.emplace_back(glm::max(e, Color(0.0f)) * kInvPi, 0.0f);
    }
    for (size_t di = 0; di < draw_instances.size(); ++di)
      if (draw_instances[di] == inst) draw_cube[di] = cube + 1;
  }
  out->cubes = std::move(cubes);
  out->draw_cube = std::move(draw_cube);
}

}  // namespace illum::realtime
