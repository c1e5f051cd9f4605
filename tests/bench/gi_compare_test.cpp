// gi-compare's figures (bench/suites/gi_compare.h) on 8×8 images whose answers are known: a
// floor (top half) and a wall (bottom half), grey light growing along x, two reference runs
// 10 % either side of their mean.
#include "gi_compare.h"

#include <gtest/gtest.h>

#include <cmath>

#include "illum/core/error.h"

namespace illum::bench {
namespace {

constexpr int kSize = 8;

float light(int x) {
  return 0.1f + 0.01f * float(x);
}

struct Inputs {
  Image no_gi{kSize, kSize, 3, 0.5f}, gi{kSize, kSize, 3}, normals{kSize, kSize, 3};
  std::vector<Image> refs{Image(kSize, kSize, 3), Image(kSize, kSize, 3)};
};

// The real-time term is `floor_gain` × the reference on the floor, `wall_gain` × on the wall.
Inputs make(float floor_gain, float wall_gain) {
  Inputs in;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const bool floor = y < kSize / 2;
      in.normals.set_rgb(x, y, floor ? Color(0.5f, 1.0f, 0.5f) : Color(1.0f, 0.5f, 0.5f));
      in.gi.set_rgb(x, y, Color(0.5f + (floor ? floor_gain : wall_gain) * light(x)));
      in.refs[0].set_rgb(x, y, Color(1.1f * light(x)));
      in.refs[1].set_rgb(x, y, Color(0.9f * light(x)));
    }
  return in;
}

double figure(const GiComparison& c, const char* region, const char* name) {
  const nlohmann::json& j = region ? c.figures["regions"][region] : c.figures["image"];
  return j[name].get<double>();
}

TEST(GiCompare, TwiceTheLightIsScaleTwoAndNoErrorAtThatScale) {
  const Inputs in = make(2.0f, 2.0f);
  const GiComparison c = compare_gi(in.no_gi, in.gi, in.refs, in.normals);
  EXPECT_NEAR(c.scale, 2.0, 1e-5);
  EXPECT_NEAR(figure(c, nullptr, "scale"), 2.0, 1e-5);
  EXPECT_NEAR(figure(c, nullptr, "rel_l1"), 0.0, 1e-5);
  EXPECT_NEAR(figure(c, nullptr, "rel_rmse"), 0.0, 1e-5);
  // Each run is 10 % off their mean: E|mean − truth| is estimated by |a − b|/2 = 0.1·P.
  EXPECT_NEAR(figure(c, nullptr, "reference_rel_l1"), 0.1, 1e-5);
  // σ per pixel 0.1·P, so RMSE / mean P = 0.1·√mean(P²) / mean P.
  double p1 = 0, p2 = 0;
  for (int x = 0; x < kSize; ++x) p1 += light(x) / kSize, p2 += light(x) * light(x) / kSize;
  EXPECT_NEAR(figure(c, nullptr, "reference_rel_rmse"), 0.1 * std::sqrt(p2) / p1, 1e-5);
  EXPECT_EQ(figure(c, "floor", "pixels"), kSize * kSize / 2);
  EXPECT_EQ(figure(c, "walls", "pixels"), kSize * kSize / 2);
  EXPECT_EQ(figure(c, "ceiling", "pixels"), 0);
  // Rows 2–5 lie within two pixels of the turn between floor and wall.
  EXPECT_EQ(figure(c, "creases", "pixels"), 4 * kSize);
}

TEST(GiCompare, RegionsKeepTheirOwnScaleAndTheImageScaleIsDividedOut) {
  const Inputs in = make(1.0f, 3.0f);
  const GiComparison c = compare_gi(in.no_gi, in.gi, in.refs, in.normals);
  EXPECT_NEAR(c.scale, 2.0, 1e-5);  // both halves hold the same reference light
  EXPECT_NEAR(figure(c, "floor", "scale"), 1.0, 1e-5);
  EXPECT_NEAR(figure(c, "walls", "scale"), 3.0, 1e-5);
  // With k = 2 divided out the floor has half its light, the wall 1.5×: |error| = P/2.
  EXPECT_NEAR(figure(c, nullptr, "rel_l1"), 0.5, 1e-5);
  EXPECT_NEAR(figure(c, "floor", "rel_l1"), 0.5, 1e-5);
  EXPECT_NEAR(figure(c, "walls", "rel_l1"), 0.5, 1e-5);
}

TEST(GiCompare, PixelsWithoutASurfaceCountForTheImageOnly) {
  Inputs in = make(2.0f, 2.0f);
  in.normals.set_rgb(3, 1, Color(0.0f));  // the normals view's black: no hit
  const GiComparison c = compare_gi(in.no_gi, in.gi, in.refs, in.normals);
  EXPECT_EQ(c.region[size_t(1) * kSize + 3], -1);
  EXPECT_EQ(figure(c, "floor", "pixels"), kSize * kSize / 2 - 1);
  EXPECT_EQ(figure(c, nullptr, "pixels"), kSize * kSize);
}

TEST(GiCompare, ADarkReferenceIsAnError) {
  Inputs in = make(2.0f, 2.0f);
  for (Image& r : in.refs) r = Image(kSize, kSize, 3, 0.0f);
  EXPECT_THROW(compare_gi(in.no_gi, in.gi, in.refs, in.normals), Error);
}

}  // namespace
}  // namespace illum::bench
