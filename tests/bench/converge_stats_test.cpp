// bench/suites/converge_stats.h: the equal-noise estimator of `illum-bench converge` and the unit
// conversions of its Cycles peer.
#include "converge_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "illum/core/error.h"
#include "illum/core/image.h"

namespace illum::bench {
namespace {

Image filled(int w, int h, const Color& c) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.set_rgb(x, y, c);
  return img;
}

// Relative tolerance for sums of a few thousand float-converted terms: float inputs carry a
// relative error of 2^-24 each, which the double sum does not grow past 1e-6.
constexpr double kFloatTol = 1e-6;

TEST(ConvergeStats, RelativeVarianceOfAKnownDifference) {
  // A = R + d, B = R − d: (A − B)²/2 = 2d² at every pixel and channel; ε = (0.01 · 2)².
  const Image ref = filled(8, 4, Color(2.0f)), a = filled(8, 4, Color(2.25f)),
              b = filled(8, 4, Color(1.75f));
  const RelativeVariance v = relative_variance(a, b, ref);
  const double eps = 0.02 * 0.02;
  EXPECT_NEAR(v.epsilon, eps, eps * kFloatTol);
  EXPECT_EQ(v.terms, 8u * 4u * 3u);
  const double expected = 2.0 * 0.25 * 0.25 / (4.0 + eps);
  EXPECT_NEAR(v.value, expected, expected * kFloatTol);
}

TEST(ConvergeStats, FloorWeighsBlackPixelsAsOnePercentOfTheMean) {
  // Half the reference black, half 2 (mean 1): the black half is divided by ε = 0.01², not 0.
  Image ref(2, 1, 3), a(2, 1, 3), b(2, 1, 3);
  ref.set_rgb(0, 0, Color(0.0f));
  ref.set_rgb(1, 0, Color(2.0f));
  a.set_rgb(0, 0, Color(0.001f));
  b.set_rgb(0, 0, Color(0.0f));
  a.set_rgb(1, 0, Color(2.0f));
  b.set_rgb(1, 0, Color(2.0f));
  const RelativeVariance v = relative_variance(a, b, ref);
  const double eps = 1e-4;
  const double expected = (0.5 * 1e-6 / eps) / 2.0;  // one of the two pixels has a difference
  EXPECT_NEAR(v.value, expected, expected * 1e-5);   // 0.001f is 0.001 to 5e-8 relative
}

TEST(ConvergeStats, EstimatesTheVarianceOfIndependentRenders) {
  // A and B = R + independent N(0, σ²) per pixel and channel: E[v] = σ² / (R² + ε). Each term
  // is σ²/(R²+ε) · χ²₁, of variance 2 (σ²/(R²+ε))², so the mean of n terms has a relative
  // standard deviation √(2/n); the check allows 5 of them.
  const int w = 64, h = 64;
  const float r = 3.0f, sigma = 0.3f;
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, sigma);
  const Image ref = filled(w, h, Color(r));
  Image a(w, h, 3), b(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      a.set_rgb(x, y, Color(r + noise(rng), r + noise(rng), r + noise(rng)));
      b.set_rgb(x, y, Color(r + noise(rng), r + noise(rng), r + noise(rng)));
    }
  const RelativeVariance v = relative_variance(a, b, ref);
  const double expected = double{sigma} * sigma / (double{r} * r + v.epsilon);
  const double n = static_cast<double>(v.terms);
  EXPECT_NEAR(v.value, expected, 5.0 * std::sqrt(2.0 / n) * expected);
}

TEST(ConvergeStats, RelativeVarianceIgnoresTheImageScale) {
  // A renderer whose whole image is k times brighter (a unit mismatch) has the same v.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.5f, 1.5f);
  Image a(16, 16, 3), b(16, 16, 3), ref(16, 16, 3), ka(16, 16, 3), kb(16, 16, 3), kref(16, 16, 3);
  const float k = 3.5f;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const Color ca(u(rng), u(rng), u(rng)), cb(u(rng), u(rng), u(rng)),
          cr(u(rng), u(rng), u(rng));
      a.set_rgb(x, y, ca), b.set_rgb(x, y, cb), ref.set_rgb(x, y, cr);
      ka.set_rgb(x, y, k * ca), kb.set_rgb(x, y, k * cb), kref.set_rgb(x, y, k * cr);
    }
  const double v = relative_variance(a, b, ref).value, vk = relative_variance(ka, kb, kref).value;
  EXPECT_NEAR(vk, v, v * kFloatTol);
}

TEST(ConvergeStats, RejectsBadImages) {
  const Image ref = filled(4, 4, Color(1.0f)), small = filled(4, 3, Color(1.0f));
  EXPECT_THROW(relative_variance(ref, small, ref), Error);
  EXPECT_THROW(relative_variance(ref, ref, small), Error);
  EXPECT_THROW(relative_variance(ref, ref, filled(4, 4, Color(0.0f))), Error);
  EXPECT_THROW(relative_variance(ref, ref, Image()), Error);
  Image nan = ref;
  nan.set_rgb(1, 1, Color(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_THROW(relative_variance(nan, ref, ref), Error);
}

TEST(ConvergeStats, EfficiencyIsOneOverVarianceTimesTime) {
  EXPECT_DOUBLE_EQ(efficiency(0.5, 4.0), 0.5);
  EXPECT_DOUBLE_EQ(efficiency(1e-3, 2.0), 500.0);
  EXPECT_THROW(efficiency(0.0, 1.0), Error);
  EXPECT_THROW(efficiency(1.0, 0.0), Error);
  EXPECT_THROW(efficiency(-1.0, 1.0), Error);
  EXPECT_THROW(efficiency(std::numeric_limits<double>::quiet_NaN(), 1.0), Error);
  EXPECT_THROW(efficiency(1.0, std::numeric_limits<double>::infinity()), Error);
}

TEST(ConvergeStats, ReferenceVarianceScalesWithTheSampleCount) {
  EXPECT_DOUBLE_EQ(reference_relative_variance(0.04, 256, 1024), 0.01);
  EXPECT_DOUBLE_EQ(reference_relative_variance(0.2, 16, 2048), 0.2 * 16.0 / 2048.0);
  EXPECT_THROW(reference_relative_variance(0.1, 0, 16), Error);
}

TEST(ConvergeStats, ImageMeanOverPixelsAndChannels) {
  Image img(2, 1, 3);
  img.set_rgb(0, 0, Color(1.0f, 2.0f, 3.0f));
  img.set_rgb(1, 0, Color(0.0f, 0.0f, 6.0f));
  EXPECT_DOUBLE_EQ(image_mean(img), 2.0);
}

TEST(ConvergeStats, CyclesUnits) {
  // A point light of P watts in Cycles has intensity P/(4π) W/sr.
  EXPECT_DOUBLE_EQ(cycles_point_power(1.0), 4.0 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(cycles_point_power(300.0 / 1.4700), 4.0 * std::numbers::pi * 300.0 / 1.4700);
  // The IES spot: the same power divided by the profile scale Cycles applies.
  EXPECT_DOUBLE_EQ(cycles_ies_spot_power(2.0), 8.0 * std::numbers::pi / kCyclesIesScale);
  // illum's max_bounces counts the first hit; Cycles' does not.
  EXPECT_EQ(cycles_max_bounces(8), 7);
  EXPECT_EQ(cycles_max_bounces(1), 0);
  EXPECT_THROW(cycles_max_bounces(0), Error);
}

}  // namespace
}  // namespace illum::bench
