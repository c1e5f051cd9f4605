#include "illum/realtime/realtime_lights.h"

#include <cmath>

#include "illum/core/error.h"

namespace illum::realtime {

bool lit_in_real_time(const Light& l) {
  return l.type == LightType::kPoint || l.type == LightType::kSpot ||
         l.type == LightType::kDirectional;
}

std::vector<Light> realtime_lights(const Scene& scene) {
  std::vector<Light> out;
  for (const Light& l : scene.lights) {
    if (l.type != LightType::kArea) {
      out.push_back(l);
      continue;
    }
    const std::string name = l.name.empty() ? "area light" : fmt::format("area light '{}'", l.name);
    if (l.instance < 0 || static_cast<size_t>(l.instance) >= scene.instances.size())
      throw Error(
          fmt::format("{} refers to instance {} of {}", name, l.instance, scene.instances.size()));
    const Instance& inst = scene.instances[static_cast<size_t>(l.instance)];
    const Mesh& m = scene.meshes.at(static_cast<size_t>(inst.mesh));
    if (m.material < 0 || static_cast<size_t>(m.material) >= scene.materials.size())
      throw Error(fmt::format("{}: its mesh has no material to emit with", name));
    const Material& mat = scene.materials[static_cast<size_t>(m.material)];
    float area = 0.0f;
    vec3 centroid(0.0f), normal(0.0f);
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      const vec3 a = vec3(inst.transform * vec4(m.positions[m.indices[t]], 1.0f));
      const vec3 b = vec3(inst.transform * vec4(m.positions[m.indices[t + 1]], 1.0f));
      const vec3 c = vec3(inst.transform * vec4(m.positions[m.indices[t + 2]], 1.0f));
      const vec3 n = glm::cross(b - a, c - a);
      const float ta = 0.5f * glm::length(n);
      area += ta;
      centroid += ta * (a + b + c) / 3.0f;
      normal += n;
    }
    // A zero-area emitter has no direction to face and no power: bad input, not a light
    // to drop silently (the offline renderers would not see it either).
    if (!(area > 0.0f) || !std::isfinite(area) || !(glm::length(normal) > 0.0f))
      throw Error(fmt::format("{} (instance {}) has zero area", name, l.instance));
    Light spot;
    spot.name = l.name + " (area as Lambertian spot)";
    spot.type = LightType::kSpot;
    spot.direction = glm::normalize(normal);
    // Just in front of the emitter, so its own triangles lie behind the light (outside the
    // cone, and inside the shadow maps' near plane); 1e-3 of the emitter's size keeps the
    // 1/d² error below 0.1% wherever the far-field model holds.
    spot.position = centroid / area + spot.direction * (1e-3f * std::sqrt(area));
    spot.cone_half_angle = radians(89.9f);
    // Seen from a distance, a flat one-sided Lambertian emitter of radiance L and area A has
    // intensity I(θ) = L·A·cos θ about its normal (flux π·L·A).
    spot.intensity = mat.emission * area;
    spot.cosine_falloff = true;
    spot.range = l.range;
    out.push_back(spot);
  }
  return out;
}

}  // namespace illum::realtime
