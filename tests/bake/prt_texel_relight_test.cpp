// Texel relighting in its three storage forms (bake/prt_texel_relight.h): fp32 against a
// double-precision sum, the half conversion exactly (every half value round trips; the
// rounding cases by value), fp16 within the bound its rounding allows, VQ equal to relighting
// each texel's representative, and the errors for mismatched inputs.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "illum/bake/prt_texel_relight.h"
#include "illum/core/error.h"
#include "illum/core/rng.h"

namespace illum::bake {
namespace {

ShLight random_light(int bands, Rng& rng) {
  ShLight l;
  l.bands = bands;
  for (int i = 0; i < bands * bands; ++i)
    l.coefficients.emplace_back(rng.next_float() * 2 - 1, rng.next_float() * 2 - 1,
                                rng.next_float() * 2 - 1);
  return l;
}

std::vector<float> random_transfer(size_t texels, int bands, Rng& rng) {
  std::vector<float> t(texels * 3 * size_t(bands * bands));
  for (float& v : t) v = (rng.next_float() * 2 - 1) * 0.7f;
  return t;
}

// Σ_i T_i L_i per channel in double, and Σ |T_i L_i| (the scale of the rounding error).
void reference(const float* t, const ShLight& l, double out[3], double mag[3]) {
  for (int c = 0; c < 3; ++c) out[c] = mag[c] = 0.0;
  for (size_t i = 0; i < l.coefficients.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double p = double(t[3 * i + size_t(c)]) * double(l.coefficients[i][c]);
      out[c] += p;
      mag[c] += std::abs(p);
    }
}

TEST(PrtTexelRelight, Fp32MatchesADoubleSumForEveryBandCount) {
  Rng rng(7);
  for (int bands = 2; bands <= 8; ++bands) {  // odd band counts end in a partial block
    const size_t texels = 1000;
    const std::vector<float> t = random_transfer(texels, bands, rng);
    const ShLight light = random_light(bands, rng);
    std::vector<float> out(3 * texels, -1.0f);
    relight_texels(std::span<const float>(t), bands, light, out);
    for (size_t x = 0; x < texels; ++x) {
      double want[3], mag[3];
      reference(&t[x * 3 * size_t(bands * bands)], light, want, mag);
      for (int c = 0; c < 3; ++c)  // float accumulation of n² products: a few ulps of Σ|p|
        ASSERT_NEAR(out[3 * x + size_t(c)], want[c], 4 * bands * bands * 6e-8 * mag[c] + 1e-30)
            << "bands " << bands << " texel " << x << " channel " << c;
    }
  }
}

TEST(PrtTexelRelight, EveryHalfRoundTrips) {
  for (uint32_t h = 0; h < 65536; ++h) {
    const float f = half_to_float(uint16_t(h));
    if (std::isnan(f)) continue;  // NaN payloads need not survive
    const std::vector<uint16_t> back = to_half(std::span<const float>(&f, 1));
    ASSERT_EQ(back[0], h) << "half " << h << " = " << f;
  }
  EXPECT_TRUE(std::isnan(half_to_float(to_half(std::vector<float>{NAN})[0])));
}

TEST(PrtTexelRelight, HalfRoundingByValue) {
  const std::vector<float> v = {1.0f,
                                -2.0f,
                                65504.0f,
                                65519.0f,  // rounds down to the largest half
                                65520.0f,  // rounds up past it: inf
                                std::ldexp(1.0f, -24),
                                std::ldexp(1.0f, -25),  // half way to 2⁻²⁴: even (0)
                                std::ldexp(3.0f, -26),  // 1.5 × 2⁻²⁵: rounds to 2⁻²⁴
                                1.0f + std::ldexp(1.0f, -11),   // half way: even (1.0)
                                1.0f + std::ldexp(3.0f, -12),   // ¾ ulp: up (0x3c01)
                                1.0f + std::ldexp(3.0f, -11)};  // 1½ ulp: even (0x3c02)
  const std::vector<uint16_t> want = {0x3c00, 0xc000, 0x7bff, 0x7bff, 0x7c00, 0x0001,
                                      0x0000, 0x0001, 0x3c00, 0x3c01, 0x3c02};
  const std::vector<uint16_t> got = to_half(v);
  for (size_t i = 0; i < v.size(); ++i) EXPECT_EQ(got[i], want[i]) << "value " << v[i];
}

TEST(PrtTexelRelight, Fp16WithinItsRounding) {
  Rng rng(11);
  for (int bands : {3, 4}) {
    const size_t texels = 5000;
    const std::vector<float> t = random_transfer(texels, bands, rng);
    const std::vector<uint16_t> h = to_half(t);
    const ShLight light = random_light(bands, rng);
    std::vector<float> out(3 * texels);
    relight_texels(std::span<const uint16_t>(h), bands, light, out);
    double worst = 0.0;
    for (size_t x = 0; x < texels; ++x) {
      double want[3], mag[3];
      reference(&t[x * 3 * size_t(bands * bands)], light, want, mag);
      for (int c = 0; c < 3; ++c) {
        // Each coefficient off by at most 2⁻¹¹ of itself, plus the float sum's ulps.
        const double bound = (std::ldexp(1.0, -11) + 4 * bands * bands * 6e-8) * mag[c];
        const double err = std::abs(out[3 * x + size_t(c)] - want[c]);
        ASSERT_LE(err, bound) << "bands " << bands << " texel " << x;
        worst = std::max(worst, err / bound);
      }
    }
    EXPECT_GT(worst, 0.01) << "the halves were not rounded at all?";
  }
}

TEST(PrtTexelRelight, VqGivesEachTexelItsRepresentative) {
  Rng rng(3);
  const int bands = 4;
  VqCodebook cb;
  cb.dimension = 3 * bands * bands;
  cb.representatives = random_transfer(37, bands, rng);
  for (int i = 0; i < 2000; ++i) cb.indices.push_back(uint16_t(rng.next_bounded(37)));
  const ShLight light = random_light(bands, rng);
  std::vector<float> out(3 * cb.indices.size()), rep(3);
  relight_texels(cb, bands, light, out);
  for (size_t x = 0; x < cb.indices.size(); ++x) {
    relight_texels(std::span<const float>(&cb.representatives[cb.indices[x] * size_t(cb.dimension)],
                                          size_t(cb.dimension)),
                   bands, light, rep);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(out[3 * x + size_t(c)], rep[size_t(c)]) << x;
  }
}

TEST(PrtTexelRelight, MismatchedInputsThrow) {
  Rng rng(5);
  const std::vector<float> t = random_transfer(10, 4, rng);
  std::vector<float> out(30);
  EXPECT_THROW(relight_texels(std::span<const float>(t), 4, random_light(3, rng), out), Error);
  std::vector<float> short_out(27);
  EXPECT_THROW(relight_texels(std::span<const float>(t), 4, random_light(4, rng), short_out),
               Error);
  VqCodebook cb;
  cb.dimension = 48;
  cb.representatives = random_transfer(2, 4, rng);
  cb.indices = {0, 1, 2};  // 2 is past the representatives
  std::vector<float> vq_out(9);
  EXPECT_THROW(relight_texels(cb, 4, random_light(4, rng), vq_out), Error);
}

}  // namespace
}  // namespace illum::bake
