#include "illum/bake/lightmap_basis.h"

#include <algorithm>
#include <cmath>

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
    case LightmapBasis::kDominant:
      return "dominant";
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
  for (const LightmapBasis b :
       {LightmapBasis::kPlain, LightmapBasis::kRnm, LightmapBasis::kShL1, LightmapBasis::kDominant})
    if (name == to_string(b)) return b;
  throw Error(fmt::format("light-map basis must be plain, rnm, sh or dominant, not '{}'", name));
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
    case LightmapBasis::kDominant:
      return 3;
  }
  throw Error(fmt::format("light-map bake: unknown basis {}", static_cast<int>(basis)));
}

LightmapBasis accumulation_basis(LightmapBasis basis) {
  return basis == LightmapBasis::kDominant ? LightmapBasis::kShL1 : basis;
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
    case LightmapBasis::kShL1:
    case LightmapBasis::kDominant: {
      // Tangent space: x = t, y = b, z = n (the SH pole is the normal, core/sh.h).
      const vec4 y = sh::evaluate_l1(vec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)));
      for (int i = 0; i < 4; ++i) out[i] = y[i];
      return;
    }
  }
}

std::vector<Image> dominant_from_sh(const std::vector<Image>& sh) {
  if (sh.size() != 4)
    throw Error(fmt::format("dominant light-map: needs the 4 SH-L1 layers, got {}", sh.size()));
  const int w = sh[0].width(), h = sh[0].height();
  for (const Image& layer : sh)
    if (layer.width() != w || layer.height() != h || layer.channels() < 3)
      throw Error("dominant light-map: the SH-L1 layers differ in size or are not RGB");
  const float y00 = static_cast<float>(sh::kY00), y1 = static_cast<float>(sh::kY1);
  std::vector<Image> out;
  for (int j = 0; j < 3; ++j) out.emplace_back(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Color c0 = sh[0].rgb(x, y), c1 = sh[1].rgb(x, y), c2 = sh[2].rgb(x, y),
                  c3 = sh[3].rgb(x, y);
      // ∫ L ω dω per channel (x = t, y = b, z = n) and ∫ L dω.
      const vec3 v[3] = {vec3(c3.x, c1.x, c2.x) / y1, vec3(c3.y, c1.y, c2.y) / y1,
                         vec3(c3.z, c1.z, c2.z) / y1};
      const Color s = c0 / y00;
      const vec3 mean =
          vec3(luminance(Color(v[0].x, v[1].x, v[2].x)), luminance(Color(v[0].y, v[1].y, v[2].y)),
               luminance(Color(v[0].z, v[1].z, v[2].z)));
      const float len = glm::length(mean);
      const vec3 d = len > 0.0f && std::isfinite(len) ? mean / len : vec3(0.0f, 0.0f, 1.0f);
      const Color e0 = c2 / (kPi * y1);
      const float dz = std::max(d.z, kMinDirectionZ);
      const float grazing = std::min(1.0f, std::max(d.z, 0.0f) / kMinDirectionZ);
      Color a, c;
      for (int ch = 0; ch < 3; ++ch) {
        const float r = s[ch] > 0.0f ? glm::dot(v[ch], d) / s[ch] : 0.0f;
        const float f = std::clamp(2.0f * r - 1.0f, 0.0f, 1.0f) * grazing;
        c[ch] = f * e0[ch] / dz;
        a[ch] = e0[ch] - c[ch] * d.z;
      }
      out[0].set_rgb(x, y, a);
      out[1].set_rgb(x, y, c);
      out[2].set_rgb(x, y, Color(d.x, d.y, d.z));
    }
  return out;
}

}  // namespace illum::bake
