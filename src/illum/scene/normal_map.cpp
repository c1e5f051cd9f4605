#include "illum/scene/normal_map.h"

#include <cmath>

namespace illum {

const Image* normal_map_of(const Scene& scene, const Material& material) {
  const int tex = material.normal_texture;
  if (tex < 0 || static_cast<size_t>(tex) >= scene.textures.size()) return nullptr;
  const Image& image = scene.textures[static_cast<size_t>(tex)].image;
  return image.empty() ? nullptr : &image;
}

bool mapped_normal(const Image& map, float normal_scale, const vec2& uv0, const vec3& tangent,
                   const vec3& bitangent, const vec3& normal, vec3* out) {
  const Color c = map.sample_bilinear(uv0.x, uv0.y);
  vec3 m = 2.0f * vec3(c) - 1.0f;
  m.x *= normal_scale;
  m.y *= normal_scale;
  const vec3 mapped = m.x * tangent + m.y * bitangent + m.z * normal;
  const float len = glm::length(mapped);
  if (!(len > 0.0f) || !std::isfinite(len)) return false;
  *out = mapped / len;
  return true;
}

}  // namespace illum
