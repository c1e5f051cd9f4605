#include "illum/bake/lightmap_basis.h"

#include <algorithm>

#include "illum/core/error.h"
#include "illum/core/sh.h"

namespace illum::bake {

const char* to_string(LightmapBasis basis) {
  switch (basis) {
    case LightmapBasis::kPlain:
      return "plain";
    case LightmapBasis::kRnm:
      return "rnm";
    case LightmapBasis::kShL1:
      return "sh";
  }
  return "unknown";
}

const char* to_string(LightmapContent content) {
  switch (content) {
    case LightmapContent::kAll:
      return "all";
    case LightmapContent::kIndirect:
      return "indirect";
  }
  return "unknown";
}

LightmapBasis lightmap_basis_from_string(const std::string& name) {
  for (const LightmapBasis b : {LightmapBasis::kPlain, LightmapBasis::kRnm, LightmapBasis::kShL1})
    if (name == to_string(b)) return b;
  throw Error(fmt::format("light-map basis must be plain, rnm or sh, not '{}'", name));
}

LightmapContent lightmap_content_from_string(const std::string& name) {
  for (const LightmapContent c : {LightmapContent::kAll, LightmapContent::kIndirect})
    if (name == to_string(c)) return c;
  throw Error(fmt::format("light-map content must be all or indirect, not '{}'", name));
}

int layer_count(LightmapBasis basis) {
  switch (basis) {
    case LightmapBasis::kPlain:
      return 1;
    case LightmapBasis::kRnm:
      return 3;
    case LightmapBasis::kShL1:
      return 4;
  }
  throw Error(fmt::format("light-map bake: unknown basis {}", static_cast<int>(basis)));
}

void basis_weights(LightmapBasis basis, const vec3& w, const vec3& n, const vec3& t, const vec3& b,
                   float* out) {
  switch (basis) {
    case LightmapBasis::kPlain:
      out[0] = glm::dot(w, n) * kInvPi;
      return;
    case LightmapBasis::kRnm: {
      const vec3 l(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n));
      for (int i = 0; i < 3; ++i)
        out[i] =
            std::max(0.0f, kRnmBasis[i][0] * l.x + kRnmBasis[i][1] * l.y + kRnmBasis[i][2] * l.z) *
            kInvPi;
      return;
    }
    case LightmapBasis::kShL1: {
      // Tangent space: x = t, y = b, z = n (the SH pole is the normal, core/sh.h).
      const vec4 y = sh::evaluate_l1(vec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)));
      for (int i = 0; i < 4; ++i) out[i] = y[i];
      return;
    }
  }
}

}  // namespace illum::bake
