#include "illum/realtime/renderer_input.h"

#include <cmath>
#include <string>

#include "illum/core/error.h"

namespace illum::realtime {

namespace {

bool finite(const vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool finite_non_negative(const Color& c) {
  return finite(c) && c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f;
}

std::string text(const vec3& v) {
  return fmt::format("({}, {}, {})", v.x, v.y, v.z);
}

std::string light_name(const Light& light, size_t index) {
  return light.name.empty() ? fmt::format("light {}", index)
                            : fmt::format("light {} ('{}')", index, light.name);
}

}  // namespace

void check_single_light(int single_light, size_t light_count) {
  if (single_light >= 0 && static_cast<size_t>(single_light) >= light_count)
    throw Error(
        fmt::format("parameter 'lighting.single_light' = {} names no light (the scene has {})",
                    single_light, light_count));
}

void check_realtime_scene(const Scene& scene) {
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const std::string name =
        mesh.name.empty() ? fmt::format("mesh {}", m) : fmt::format("mesh {} ('{}')", m, mesh.name);
    if (mesh.indices.size() % 3 != 0)
      throw Error(fmt::format("{} has {} indices, not a multiple of 3", name, mesh.indices.size()));
    for (const uint32_t i : mesh.indices)
      if (i >= mesh.positions.size())
        throw Error(
            fmt::format("{} has vertex index {} of {} vertices", name, i, mesh.positions.size()));
    for (const vec3& p : mesh.positions)
      if (!finite(p)) throw Error(fmt::format("{} has a non-finite vertex {}", name, text(p)));
  }
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= scene.meshes.size())
      throw Error(
          fmt::format("instance {} refers to mesh {} of {}", i, inst.mesh, scene.meshes.size()));
    for (int c = 0; c < 4; ++c)
      if (!finite(vec3(inst.transform[c])) || !std::isfinite(inst.transform[c][3]))
        throw Error(fmt::format("instance {} has a non-finite transform", i));
  }
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    const std::string name = m.name.empty() ? fmt::format("material {}", i)
                                            : fmt::format("material {} ('{}')", i, m.name);
    if (!finite_non_negative(m.albedo) || !finite_non_negative(m.specular) ||
        !finite_non_negative(m.emission))
      throw Error(fmt::format("{}: albedo, specular and emission must be finite and ≥ 0", name));
    if (!(m.exponent >= 0.0f) || !std::isfinite(m.exponent) || !std::isfinite(m.normal_scale))
      throw Error(
          fmt::format("{}: the exponent must be finite and ≥ 0, the normal scale finite", name));
  }
}

void check_realtime_lights(const std::vector<Light>& lights) {
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& l = lights[i];
    if (!lit_in_real_time(l)) continue;  // environment lights pass through unlit
    const std::string name = light_name(l, i);
    if (l.type != LightType::kDirectional && !finite(l.position))
      throw Error(fmt::format("{} has a non-finite position {}", name, text(l.position)));
    if (l.type != LightType::kPoint && !(finite(l.direction) && glm::length(l.direction) > 0.0f))
      throw Error(fmt::format("{} has direction {}: it must be finite and not zero", name,
                              text(l.direction)));
    if (l.type == LightType::kDirectional) {
      if (!finite_non_negative(l.irradiance))
        throw Error(fmt::format("{} has irradiance {}: it must be finite and ≥ 0", name,
                                text(l.irradiance)));
    } else if (!finite_non_negative(l.intensity)) {
      throw Error(
          fmt::format("{} has intensity {}: it must be finite and ≥ 0", name, text(l.intensity)));
    }
    if (l.type == LightType::kSpot &&
        !(l.cone_half_angle > 0.0f && l.cone_half_angle <= 0.5f * kPi))
      throw Error(fmt::format("{} has a cone half angle of {} rad, outside (0, π/2]", name,
                              l.cone_half_angle));
    if (!(l.range >= 0.0f) || !std::isfinite(l.range))
      throw Error(
          fmt::format("{} has range {}: it must be finite and ≥ 0 (0: unlimited)", name, l.range));
  }
}

void check_realtime_input(const Scene& scene, int single_light) {
  try {
    check_realtime_scene(scene);
    const std::vector<Light> lights = realtime_lights(scene);
    check_realtime_lights(lights);
    check_single_light(single_light, lights.size());
  } catch (const Error& e) {
    if (scene.source_path.empty()) throw;
    throw Error(fmt::format("{}: {}", scene.source_path, e.what()));
  }
}

void check_camera(const Camera& c) {
  if (!finite(c.position) || !finite(c.look_at) || !finite(c.up))
    throw Error(fmt::format("camera: position {}, look_at {} and up {} must be finite",
                            text(c.position), text(c.look_at), text(c.up)));
  const vec3 forward = c.look_at - c.position;
  if (!(glm::length(forward) > 0.0f) || !(glm::length(glm::cross(forward, c.up)) > 0.0f))
    throw Error(
        fmt::format("camera: look_at {} must differ from position {} and not lie along up {}",
                    text(c.look_at), text(c.position), text(c.up)));
  if (!(c.fov_y > 0.0f && c.fov_y < kPi))
    throw Error(fmt::format("camera: vertical field of view {} rad is outside (0, π)", c.fov_y));
}

}  // namespace illum::realtime
