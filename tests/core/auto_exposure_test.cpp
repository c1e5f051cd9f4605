// The auto-exposure rule (core/auto_exposure.h) on synthetic images whose answer is known.
#include "illum/core/auto_exposure.h"

#include <cmath>

#include <gtest/gtest.h>

namespace illum {
namespace {

Image uniform(int w, int h, float l) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.set_rgb(x, y, Color(l));
  return img;
}

// The centre of bin i in log2 luminance, where the rule is exact.
double bin_centre(int i) {
  return exposure::kMinLog2 + (i + 0.5) * double(kExposureBinWidth);
}

TEST(AutoExposure, UniformImageAtABinCentreGetsExactlyTargetOverItsLuminance) {
  for (int bin : {3, 100, 128, 200, 250}) {
    const float l = float(std::exp2(bin_centre(bin)));
    const AutoExposure a = auto_exposure(uniform(8, 6, l));
    EXPECT_EQ(a.counted, 48u);
    EXPECT_FLOAT_EQ(a.mean_log2, float(bin_centre(bin))) << bin;
    EXPECT_FLOAT_EQ(a.exposure, exposure::kTarget / l) << bin;
  }
}

TEST(AutoExposure, UniformImageAnywhereIsWithinHalfABin) {
  for (float l : {1e-3f, 0.18f, 0.7f, 3.3f, 1234.5f}) {
    const AutoExposure a = auto_exposure(uniform(5, 5, l));
    EXPECT_LE(std::abs(std::log2(a.exposure * l / exposure::kTarget)), 0.5 * kExposureBinWidth)
        << l;
  }
}

// An image of two levels whose split is inside the percentile band, plus up to (1 − high)
// of blinding pixels: the exposure does not move.
TEST(AutoExposure, BrightPixelsAboveTheHighPercentileDoNotChangeIt) {
  const float dark = float(std::exp2(bin_centre(90))), lit = float(std::exp2(bin_centre(120)));
  Image img(20, 20, 3);
  for (int i = 0; i < 400; ++i) img.set_rgb(i % 20, i / 20, Color(i < 150 ? dark : lit));
  const AutoExposure before = auto_exposure(img);
  EXPECT_FLOAT_EQ(before.mean_log2, float(bin_centre(120)));
  // 4 % of the pixels (below 1 − kHighPercentile = 5 %) become 10⁶ times brighter.
  for (int i = 0; i < 16; ++i) img.set_rgb(i, 19, Color(lit * 1e6f));
  const AutoExposure after = auto_exposure(img);
  EXPECT_EQ(after.exposure, before.exposure);
  // 20 % of them: the high percentile reaches them and the exposure drops (the test can fail).
  for (int i = 0; i < 80; ++i) img.set_rgb(i % 20, 19 - i / 20, Color(lit * 1e6f));
  EXPECT_LT(auto_exposure(img).exposure, 0.5f * before.exposure);
}

TEST(AutoExposure, ImageTimesKGetsExposureOverK) {
  // A ramp over 10 stops of many bins; a scale by 2^n moves every pixel n·8 bins.
  Image img(64, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 64; ++x)
      img.set_rgb(x, y, Color(std::exp2(-5.0f + 10.0f * float(y * 64 + x) / 1024.0f)));
  const float e = auto_exposure(img).exposure;
  for (int n : {-7, -1, 1, 3, 9}) {
    const float k = std::exp2(float(n));
    Image scaled = img;
    for (size_t i = 0; i < scaled.pixel_count() * 3; ++i) scaled.data()[i] *= k;
    EXPECT_FLOAT_EQ(auto_exposure(scaled).exposure, e / k) << n;
  }
  // Any other k: within a bin.
  for (float k : {0.3f, 1.7f, 55.0f}) {
    Image scaled = img;
    for (size_t i = 0; i < scaled.pixel_count() * 3; ++i) scaled.data()[i] *= k;
    EXPECT_LE(std::abs(std::log2(auto_exposure(scaled).exposure * k / e)), kExposureBinWidth) << k;
  }
}

TEST(AutoExposure, BlackIsNotCountedAndAllBlackKeepsExposureOne) {
  const AutoExposure black = auto_exposure(uniform(4, 4, 0.0f));
  EXPECT_EQ(black.counted, 0u);
  EXPECT_EQ(black.exposure, 1.0f);
  // Half black, half at a bin centre: the black half does not drag the exposure up.
  const float l = float(std::exp2(bin_centre(140)));
  Image img = uniform(4, 4, l);
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 2; ++y) img.set_rgb(x, y, Color(0.0f));
  EXPECT_FLOAT_EQ(auto_exposure(img).exposure, exposure::kTarget / l);
}

TEST(AutoExposure, BinsCoverTheRangeAndClampAbove) {
  EXPECT_EQ(exposure_bin(0.0f), -1);
  EXPECT_EQ(exposure_bin(-1.0f), -1);
  EXPECT_EQ(exposure_bin(std::nanf("")), -1);
  EXPECT_EQ(exposure_bin(std::exp2(exposure::kMinLog2) * 0.99f), -1);
  EXPECT_EQ(exposure_bin(std::exp2(exposure::kMinLog2)), 0);
  EXPECT_EQ(exposure_bin(1.0f), exposure::kHistogramBins / 2);
  EXPECT_EQ(exposure_bin(1e30f), exposure::kHistogramBins - 1);
  EXPECT_EQ(exposure_bin(INFINITY), exposure::kHistogramBins - 1);
}

TEST(AutoExposure, DisplayExposureMultipliesOrReplaces) {
  const float l = float(std::exp2(bin_centre(130)));
  const Image img = uniform(3, 3, l);
  EXPECT_FLOAT_EQ(display_exposure(img, 2.0f, false), 2.0f * exposure::kTarget / l);
  EXPECT_EQ(display_exposure(img, 2.0f, true), 2.0f);
}

}  // namespace
}  // namespace illum
