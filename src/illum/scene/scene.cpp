#include "illum/scene/scene.h"

namespace illum {

const char* to_string(MaterialType type) {
  switch (type) {
    case MaterialType::kLambert:
      return "lambert";
    case MaterialType::kPhong:
      return "phong";
    case MaterialType::kBlinn:
      return "blinn";
    case MaterialType::kMirror:
      return "mirror";
    case MaterialType::kDielectric:
      return "dielectric";
    case MaterialType::kConductor:
      return "conductor";
  }
  return "unknown";
}

const char* to_string(LightType type) {
  switch (type) {
    case LightType::kPoint:
      return "point";
    case LightType::kSpot:
      return "spot";
    case LightType::kDirectional:
      return "directional";
    case LightType::kArea:
      return "area";
    case LightType::kEnvironment:
      return "environment";
  }
  return "unknown";
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const Instance& inst : instances) {
    if (inst.mesh >= 0 && static_cast<size_t>(inst.mesh) < meshes.size())
      n += meshes[inst.mesh].triangle_count();
  }
  return n;
}

Bounds3 Scene::bounds() const {
  // Transforms the vertices that triangles use: the 8 corners of an object-space box would
  // loosen the bounds under rotation, and unused vertices (the bunny has 1,113) are no surface.
  Bounds3 b;
  for (const Instance& inst : instances) {
    if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= meshes.size()) continue;
    const Mesh& mesh = meshes[inst.mesh];
    for (uint32_t index : mesh.indices) {
      if (index >= mesh.positions.size()) continue;
      b.extend(vec3(inst.transform * vec4(mesh.positions[index], 1.0f)));
    }
  }
  return b;
}

}  // namespace illum
