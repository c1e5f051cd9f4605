// The light propagation volume's cascade boxes (lpv_cascades.h).
#include "illum/realtime/techniques/lpv_cascades.h"

#include <algorithm>
#include <cmath>

namespace illum::realtime {

std::vector<LpvCascade> lpv_cascades(const vec3& camera, int n, int count, float cell,
                                     const Bounds3& scene) {
  const float half = 0.5f * static_cast<float>(n);
  std::vector<LpvCascade> c(static_cast<size_t>(std::max(count, 1)));
  LpvCascade& coarsest = c.back();
  if (cell > 0.0f) {
    coarsest.cell = std::ldexp(cell, static_cast<int>(c.size()) - 1);
    coarsest.lo = (glm::floor(camera / coarsest.cell) - half) * coarsest.cell;
  } else {
    const vec3 size = scene.empty() ? vec3(1.0f) : scene.extent();
    coarsest.cell = std::max({size.x, size.y, size.z, 1e-3f}) / (static_cast<float>(n) - 1.0f);
    const vec3 lo = scene.empty() ? vec3(0.0f) : scene.min;
    coarsest.lo = glm::floor(lo / coarsest.cell) * coarsest.cell;
  }
  for (size_t k = c.size() - 1; k-- > 0;) {
    const LpvCascade& outer = c[k + 1];
    const float s = 0.5f * outer.cell;
    // The centre's range: the snap below moves the box by less than one of its cells, so its
    // cells stay over kLpvNestCells − ½ outer cells inside the outer box.
    const float inset = kLpvNestCells * outer.cell + half * s;
    const vec3 centre =
        glm::clamp(camera, outer.lo + inset, outer.lo + static_cast<float>(n) * outer.cell - inset);
    c[k].cell = s;
    c[k].lo = (glm::floor(centre / s) - half) * s;
  }
  return c;
}

float lpv_inside_cells(const LpvCascade& c, int n, const vec3& p) {
  const vec3 t = (p - c.lo) / c.cell;
  const vec3 d = glm::min(t - 0.5f, vec3(static_cast<float>(n) - 0.5f) - t);
  return std::min({d.x, d.y, d.z});
}

}  // namespace illum::realtime
