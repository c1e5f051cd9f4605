#include "illum/render/material_eval.h"

namespace illum {

Color texture_color(const Scene& scene, int texture, const vec2& uv) {
  if (texture < 0 || static_cast<size_t>(texture) >= scene.textures.size()) return Color(1.0f);
  const Image& image = scene.textures[texture].image;
  if (image.empty()) return Color(1.0f);
  return image.sample_bilinear(uv.x, uv.y);
}

Color material_albedo(const Scene& scene, const Material& material, const vec2& uv0) {
  return material.albedo * texture_color(scene, material.albedo_texture, uv0);
}

Color material_emission(const Scene& scene, const Material& material, const vec2& uv0) {
  if (!material.is_emissive()) return Color(0.0f);
  return material.emission * texture_color(scene, material.emission_texture, uv0);
}

const Material& interaction_material(const Scene& scene, const SurfaceInteraction& si) {
  static const Material kDefault{};
  if (si.material < 0 || static_cast<size_t>(si.material) >= scene.materials.size())
    return kDefault;
  return scene.materials[si.material];
}

Color surface_emission(const Scene& scene, const SurfaceInteraction& si) {
  const Material& m = interaction_material(scene, si);
  if (!m.is_emissive() || glm::dot(si.wo, si.ng) <= 0.0f) return Color(0.0f);
  return material_emission(scene, m, si.uv0);
}

}  // namespace illum
