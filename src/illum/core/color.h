// Linear RGB colour (Rec.709 primaries) inside illum; sRGB only when writing 8-bit images.
#pragma once

#include <algorithm>
#include <cmath>

#include "illum/core/math.h"

namespace illum {

using Color = glm::vec3;  // linear RGB

// Lumens per watt used to turn photometric light units (glTF's candela and lux) into
// radiometric ones: 683 lm/W, the efficacy at 555 nm that defines the candela, applied to
// every colour as Blender's glTF importer and exporter do (illum has no spectra to weigh).
inline constexpr double kLuminousEfficacy = 683.0;

// Rec.709 luminance weights (green 0.7152; S000 §2.6 prints a wrong value, see ALGORITHMS.md 45).
inline float luminance(const Color& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

inline float srgb_encode(float linear) {
  linear = std::clamp(linear, 0.0f, 1.0f);
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}
inline float srgb_decode(float encoded) {
  encoded = std::clamp(encoded, 0.0f, 1.0f);
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}
inline Color srgb_encode(const Color& c) {
  return {srgb_encode(c.r), srgb_encode(c.g), srgb_encode(c.b)};
}
inline Color srgb_decode(const Color& c) {
  return {srgb_decode(c.r), srgb_decode(c.g), srgb_decode(c.b)};
}
inline bool is_black(const Color& c) {
  return c.r <= 0.0f && c.g <= 0.0f && c.b <= 0.0f;
}

}  // namespace illum
