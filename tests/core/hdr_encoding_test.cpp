// Light-map encodings for 8/10-bit export (core/hdr_encoding.h) and LRP97 histogram tone
// reproduction (core/histogram_tone.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "illum/core/error.h"
#include "illum/core/hdr_encoding.h"
#include "illum/core/histogram_tone.h"

namespace illum {
namespace {

// Log-uniform colours over [1e-4, hi] with random chroma.
std::vector<Color> hdr_colours(float hi, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Color> out;
  for (int i = 0; i < n; ++i) {
    const float l = std::exp(std::log(1e-4f) + (std::log(hi) - std::log(1e-4f)) * u(rng));
    out.push_back(Color(l * (0.2f + u(rng)), l * (0.2f + u(rng)), l * (0.2f + u(rng))));
  }
  return out;
}

TEST(HdrEncoding, RgbmRoundTripsWithinItsBound) {
  for (float range : {6.0f, 8.0f}) {
    for (const Color& raw : hdr_colours(range, 20000, 3)) {
      const Color c = glm::min(raw, Color(range));  // above the range: clamped (below)
      const Color d = decode_rgbm(encode_rgbm(c, range), range);
      const float largest = std::max({c.r, c.g, c.b});
      for (int k = 0; k < 3; ++k)
        ASSERT_LE(std::abs(d[k] - c[k]), rgbm_error_bound(largest, range))
            << "range " << range << " channel " << k << " of " << c[0] << "," << c[1] << ","
            << c[2];
    }
    // Above the range: clamped, never wrapped.
    const Color d = decode_rgbm(encode_rgbm(Color(3.0f * range, 0.5f, 0.0f), range), range);
    EXPECT_NEAR(d.r, range, 1e-5f * range);
    EXPECT_NEAR(d.g, 0.5f, rgbm_error_bound(range, range));
    EXPECT_EQ(d.b, 0.0f);
  }
  EXPECT_THROW(encode_rgbm(Color(1.0f), 0.0f), Error);
}

TEST(HdrEncoding, Rgbs10RoundTripsWithinHalfAStepOfItsScale) {
  for (const Color& raw : hdr_colours(kRgbs10Max, 20000, 5)) {
    const Color c = glm::min(raw, Color(kRgbs10Max));  // above the range: clamped (below)
    const uint32_t packed = encode_rgbs10(c);
    const Color d = decode_rgbs10(packed);
    const float m = std::max({c.r, c.g, c.b});
    // The smallest power-of-two scale (2, 4, 8, 16) that holds the largest channel.
    const float scale = std::exp2(float((packed >> 30) + 1));
    ASSERT_GE(scale, std::min(m, kRgbs10Max) - 1e-6f);
    if (scale > 2.0f) {
      ASSERT_LT(scale / 2.0f, m) << "a smaller scale would hold it";
    }
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(d[k] - c[k]), 0.5f / 1023.0f * scale + 1e-6f);
  }
  // The range is [0, 16]; the straight 10-bit format with a fixed scale of 4 reaches 4.
  EXPECT_NEAR(decode_rgbs10(encode_rgbs10(Color(20.0f, 16.0f, 1.0f))).r, 16.0f, 1e-5f);
  EXPECT_EQ(decode_rgbs10(encode_rgbs10(Color(0.0f))), Color(0.0f));
}

TEST(HistogramTone, LowDynamicRangeMapsLinearly) {
  // 1:50 fits the display's 1:100: LRP97 maps linearly, world_max to display_max.
  std::vector<float> lum;
  for (int i = 0; i < 1000; ++i) lum.push_back(0.02f + 0.98f * float(i) / 999.0f);
  const HistogramToneCurve curve(lum);
  EXPECT_TRUE(curve.linear());
  for (float l : {0.02f, 0.1f, 0.5f, 1.0f}) EXPECT_NEAR(curve.display(l), 100.0f * l, 1e-3f);
}

TEST(HistogramTone, NeverSteeperThanLinearAndSpansTheDisplay) {
  // 1:10^7 with a dense cluster near 1 (where plain equalization would be far steeper
  // than linear) and a sparse tail.
  std::vector<float> lum;
  std::mt19937 rng(11);
  std::normal_distribution<float> cluster(0.0f, 0.1f);
  std::uniform_real_distribution<float> tail(std::log(1e-4f), std::log(1e3f));
  for (int i = 0; i < 50000; ++i) lum.push_back(std::exp(cluster(rng)));
  for (int i = 0; i < 5000; ++i) lum.push_back(std::exp(tail(rng)));
  const HistogramToneCurve curve(lum);
  ASSERT_FALSE(curve.linear());
  float lo = INFINITY, hi = 0.0f;
  for (float l : lum) lo = std::min(lo, l), hi = std::max(hi, l);
  EXPECT_NEAR(curve.display(lo), 1.0f, 1e-3f);
  EXPECT_NEAR(curve.display(hi), 100.0f, 1e-2f);
  // Slope in log-log over steps of a tenth of a bin: ≤ 1 (the ceiling), with the float
  // rounding of the logarithms as slack; monotonic.
  const double step = (std::log(double(hi)) - std::log(double(lo))) / 1000.0;
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const double a = std::log(double(lo)) + i * step, b = a + step;
    const double da = std::log(double(curve.display(float(std::exp(a)))));
    const double db = std::log(double(curve.display(float(std::exp(b)))));
    ASSERT_GE(db, da - 1e-6) << "monotonic";
    worst = std::max(worst, (db - da) / step);
  }
  std::printf("steepest log-log slope %.4f\n", worst);
  EXPECT_LE(worst, 1.0 + 1e-3);
  // The cluster gets more of the display than a log-linear squeeze of the whole range
  // would give it (that is what the histogram is for).
  const double squeeze = std::log(100.0) / (std::log(double(hi)) - std::log(double(lo)));
  const double cluster_slope = (std::log(double(curve.display(std::exp(0.1f)))) -
                                std::log(double(curve.display(std::exp(-0.1f))))) /
                               0.2;
  EXPECT_GT(cluster_slope, 2.0 * squeeze);
}

TEST(HistogramTone, ImageKeepsHueAndAlphaAndRefusesBadOptions) {
  Image hdr(4, 1, 4, 1.0f);
  const Color colours[4] = {
      {1e-3f, 2e-3f, 5e-4f}, {0.5f, 0.25f, 0.1f}, {20.0f, 10.0f, 5.0f}, {0.0f, 0.0f, 0.0f}};
  for (int x = 0; x < 4; ++x) {
    hdr.set_rgb(x, 0, colours[x]);
    hdr.pixel(x, 0)[3] = 0.25f * x;
  }
  const Image out = histogram_tone_mapped(hdr);
  for (int x = 0; x < 3; ++x) {
    const Color c = out.rgb(x, 0);
    EXPECT_NEAR(c.g / c.r, colours[x].g / colours[x].r, 1e-4f) << x;  // one factor per pixel
    EXPECT_LE(std::max({c.r, c.g, c.b}), 1.0f);
  }
  EXPECT_EQ(out.rgb(3, 0), Color(0.0f));
  for (int x = 0; x < 4; ++x) EXPECT_EQ(out.pixel(x, 0)[3], 0.25f * x);
  HistogramToneOptions bad;
  bad.display_max = 0.5f;
  EXPECT_THROW(HistogramToneCurve({1.0f}, bad), Error);
  bad = {};
  bad.bins = 1;
  EXPECT_THROW(HistogramToneCurve({1.0f}, bad), Error);
}

}  // namespace
}  // namespace illum
