// The cell of a regular 3-D grid around a point and its eight corners' trilinear weights: the
// probe lookups (bake/probe_lookup.cpp on the CPU, realtime/probe_volume.cpp mirroring
// shaders/probe_volume.glsl) share it, so their corner order and weights cannot drift apart.
#pragma once

#include "illum/core/math.h"

namespace illum {

struct TrilinearCell {
  // Grid point (x, y, z) lies at origin + spacing·(x, y, z); p is clamped into the grid.
  TrilinearCell(const glm::ivec3& size, const vec3& origin, const vec3& spacing, const vec3& p) {
    const vec3 g = glm::clamp((p - origin) / spacing, vec3(0.0f), vec3(size - 1));
    i0 = glm::min(glm::ivec3(glm::floor(g)), size - 1);
    i1 = glm::min(i0 + 1, size - 1);
    t = g - vec3(i0);
  }
  // Corner k (0..7): bit 0 picks i1.x, bit 1 i1.y, bit 2 i1.z.
  glm::ivec3 corner(int k) const {
    return {k & 1 ? i1.x : i0.x, k & 2 ? i1.y : i0.y, k & 4 ? i1.z : i0.z};
  }
  float weight(int k) const {
    return (k & 1 ? t.x : 1.0f - t.x) * (k & 2 ? t.y : 1.0f - t.y) * (k & 4 ? t.z : 1.0f - t.z);
  }

  glm::ivec3 i0, i1;
  vec3 t;
};

}  // namespace illum
