#include "illum/core/tonemap.h"

#include <algorithm>

namespace illum {

ToneMapper tone_mapper_from_string(const std::string& name) {
  if (name == "clamp") return ToneMapper::kClamp;
  if (name == "reinhard") return ToneMapper::kReinhard;
  if (name == "aces") return ToneMapper::kAces;
  if (name == "agx") return ToneMapper::kAgx;
  throw Error(fmt::format("unknown tone mapper '{}' (known: clamp, reinhard, aces, agx)", name));
}

namespace {

// AgX (Sobotka): inset to a smaller gamut, log2 encoding over [−12.47, 4.03] EV, a sigmoid
// (6th-order polynomial fit of the reference contrast curve), outset, back to linear; the
// constants of shaders/tonemap.comp (column-major, as GLSL's mat3).
Color agx(const Color& c) {
  const glm::mat3 inset(0.842479062253094f, 0.0423282422610123f, 0.0423756549057051f,
                        0.0784335999999992f, 0.878468636469772f, 0.0784336f, 0.0792237451477643f,
                        0.0791661274605434f, 0.879142973793104f);
  const glm::mat3 outset(1.19687900512017f, -0.0528968517574562f, -0.0529716355144438f,
                         -0.0980208811401368f, 1.15190312990417f, -0.0980434501171241f,
                         -0.0990297440797205f, -0.0989611768448433f, 1.15107367264116f);
  const float min_ev = -12.47393f, max_ev = 4.026069f;
  Color v = inset * glm::max(c, 0.0f);
  v = glm::clamp(glm::log2(glm::max(v, 1e-10f)), min_ev, max_ev);
  v = (v - min_ev) / (max_ev - min_ev);
  const Color x2 = v * v, x4 = x2 * x2;
  v = 15.5f * x4 * x2 - 40.14f * x4 * v + 31.96f * x4 - 6.868f * x2 * v + 0.4298f * x2 +
      0.1191f * v - 0.00232f;
  v = outset * v;
  return glm::clamp(glm::pow(glm::max(v, 0.0f), Color(2.2f)), 0.0f, 1.0f);
}

}  // namespace

Color tone_map(const Color& c, ToneMapper mapper) {
  switch (mapper) {
    case ToneMapper::kClamp:
      return glm::clamp(c, 0.0f, 1.0f);
    case ToneMapper::kReinhard: {
      // Global Reinhard on luminance, so hues are kept: L / (1 + L).
      const float l = luminance(c);
      return l > 0.0f ? glm::clamp(c * (1.0f / (1.0f + l)), 0.0f, 1.0f) : Color(0.0f);
    }
    case ToneMapper::kAces: {
      // Narkowicz 2015 fit of the ACES reference rendering transform.
      const Color x = glm::max(c, 0.0f);
      return glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
    }
    case ToneMapper::kAgx:
      return agx(c);
  }
  return c;
}

Image tone_mapped(const Image& hdr, ToneMapper mapper, float exposure) {
  Image out = hdr;
  for (int y = 0; y < hdr.height(); ++y)
    for (int x = 0; x < hdr.width(); ++x) {
      float* px = out.pixel(x, y);
      const Color mapped = tone_map(hdr.rgb(x, y) * exposure, mapper);
      const int n = std::min(hdr.channels(), 3);
      for (int c = 0; c < n; ++c) px[c] = mapped[c];
    }
  return out;
}

}  // namespace illum
