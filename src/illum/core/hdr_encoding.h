// 8- and 10-bit encodings of linear HDR light (light-maps handed to engines that read LDR
// textures): RGBM (8-bit RGB times a shared multiplier in alpha, scaled by a range M) and
// RGBS 10-10-10-2 (S003 ch.3: 10-bit fixed-point RGB whose 2 alpha bits are a shared
// power-of-two scale, stretching the range from [0, 4] to [0, 16]). Both round to nearest
// and clamp what exceeds their range; `decode(encode(c))` is within the bounds the
// functions state.
#pragma once

#include <array>
#include <cstdint>

#include "illum/core/color.h"

namespace illum {

// RGBM with range `range` (> 0): c ≈ rgb · a · range, every channel in [0, 1] stored in
// 8 bits. The multiplier a is the largest channel over `range`, rounded up to the next
// 1/255 so that no channel exceeds 1; values above `range` clamp to it.
std::array<uint8_t, 4> encode_rgbm(const Color& c, float range);
Color decode_rgbm(const std::array<uint8_t, 4>& rgbm, float range);
// The largest error of any channel of a colour whose largest channel is `largest` (values
// below the range): half a step of an 8-bit channel at the colour's multiplier.
float rgbm_error_bound(float largest, float range);

// RGBS 10-10-10-2, packed as in VK_FORMAT_A2B10G10R10_UNORM_PACK32 (R in the low bits):
// c ≈ rgb / 1023 · 2^(s+1), s ∈ {0..3} the smallest scale whose range holds the largest
// channel (2, 4, 8, 16); values above 16 clamp.
uint32_t encode_rgbs10(const Color& c);
Color decode_rgbs10(uint32_t packed);
inline constexpr float kRgbs10Max = 16.0f;

}  // namespace illum
