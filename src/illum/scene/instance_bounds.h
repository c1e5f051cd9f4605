// World-space bounds of one instance's mesh positions (the probe lookups place a dynamic
// instance's ambient cube at its centre).
#pragma once

#include "illum/scene/scene.h"

namespace illum {

inline Bounds3 instance_bounds(const Scene& scene, const Instance& instance) {
  Bounds3 b;
  for (const vec3& p : scene.meshes[static_cast<size_t>(instance.mesh)].positions)
    b.extend(vec3(instance.transform * vec4(p, 1.0f)));
  return b;
}

}  // namespace illum
