#include "illum/core/hdr_encoding.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "illum/core/error.h"

namespace illum {

namespace {

float max_channel(const Color& c) {
  return std::max({c.r, c.g, c.b, 0.0f});
}

uint32_t quantize(float v, uint32_t levels) {  // v in [0, 1] → 0..levels, nearest
  return static_cast<uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * static_cast<float>(levels)));
}

}  // namespace

std::array<uint8_t, 4> encode_rgbm(const Color& c, float range) {
  if (!(range > 0.0f && std::isfinite(range)))
    throw Error(fmt::format("RGBM range must be positive and finite, got {}", range));
  const float m = std::min(max_channel(c), range) / range;
  // The multiplier rounds up, so rgb / (a · range) never exceeds 1.
  const uint32_t a = std::max<uint32_t>(1u, static_cast<uint32_t>(std::ceil(m * 255.0f)));
  const float scale = static_cast<float>(a) / 255.0f * range;
  std::array<uint8_t, 4> out{};
  for (int k = 0; k < 3; ++k)
    out[static_cast<size_t>(k)] =
        static_cast<uint8_t>(quantize(std::min(std::max(c[k], 0.0f), range) / scale, 255u));
  out[3] = static_cast<uint8_t>(a);
  return out;
}

Color decode_rgbm(const std::array<uint8_t, 4>& rgbm, float range) {
  const float scale = static_cast<float>(rgbm[3]) / 255.0f * range;
  return Color(rgbm[0] / 255.0f * scale, rgbm[1] / 255.0f * scale, rgbm[2] / 255.0f * scale);
}

float rgbm_error_bound(float largest, float range) {
  // Half a step of a channel at the multiplier in use (at most 1/255 above largest / range).
  const float a = std::min(1.0f, std::min(largest, range) / range + 1.0f / 255.0f);
  return 0.5f / 255.0f * a * range + 1e-6f * range;
}

uint32_t encode_rgbs10(const Color& c) {
  const float m = std::min(max_channel(c), kRgbs10Max);
  uint32_t s = 0;
  while (s < 3 && m > std::exp2(static_cast<float>(s + 1))) ++s;
  const float scale = std::exp2(static_cast<float>(s + 1));
  uint32_t packed = s << 30;
  for (int k = 0; k < 3; ++k)
    packed |= quantize(std::min(std::max(c[k], 0.0f), kRgbs10Max) / scale, 1023u) << (10 * k);
  return packed;
}

Color decode_rgbs10(uint32_t packed) {
  const float scale = std::exp2(static_cast<float>((packed >> 30) + 1));
  Color c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<float>((packed >> (10 * k)) & 1023u) / 1023.0f * scale;
  return c;
}

}  // namespace illum
