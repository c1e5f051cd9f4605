#include "illum/core/tonemap.h"

#include <algorithm>

namespace illum {

ToneMapper tone_mapper_from_string(const std::string& name) {
  if (name == "clamp") return ToneMapper::kClamp;
  if (name == "reinhard") return ToneMapper::kReinhard;
  if (name == "aces") return ToneMapper::kAces;
  throw Error(fmt::format("unknown tone mapper '{}' (known: clamp, reinhard, aces)", name));
}

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
