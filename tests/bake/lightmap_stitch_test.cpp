// Seam stitching keeps light non-negative: the least-squares agreement of a bright and a
// dark side moves every texel under the bright side's lookup down together, and a black
// texel sharing that lookup would go below zero. The solve holds such texels at zero
// (active set) and agrees with the rest.
#include <gtest/gtest.h>

#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/core/image.h"

namespace illum {
namespace {

// A 4 × 1 atlas, every texel covered: side 0 of each sample reads texels 0 and 1 half and
// half (x = 1.0 lies between their centres 0.5 and 1.5), side 1 reads texel 3 alone.
struct OneSeam {
  atlas::TexelRaster raster;
  bake::Seams seams;
  std::vector<Image> layers;
  OneSeam(float t0, float t1, float t3) {
    raster.width = 4;
    raster.height = 1;
    raster.sample_of = {0, 1, 2, 3};
    seams.edges = 1;
    for (int i = 0; i < 3; ++i) seams.samples.push_back({{vec2(1.0f, 0.5f), vec2(3.5f, 0.5f)}});
    Image layer(4, 1, 3, 0.0f);
    layer.set_rgb(0, 0, Color(t0));
    layer.set_rgb(1, 0, Color(t1));
    layer.set_rgb(3, 0, Color(t3));
    layers.push_back(layer);
  }
  float at(int x) const { return layers[0].rgb(x, 0).g; }
  float step() const {
    return bake::bilinear_lookup(layers[0], seams.samples[0].side[0]).g -
           bake::bilinear_lookup(layers[0], seams.samples[0].side[1]).g;
  }
};

TEST(LightmapStitch, NoTexelGoesBelowZero) {
  OneSeam s(10.0f, 0.0f, 0.0f);
  EXPECT_NEAR(s.step(), 5.0f, 1e-6f);
  const bake::SeamStitchStats stats = bake::stitch_seams(s.seams, s.raster, s.layers);
  for (int x = 0; x < 4; ++x) EXPECT_GE(s.at(x), 0.0f) << "texel " << x;
  EXPECT_EQ(s.at(1), 0.0f) << "the black texel under the bright lookup is held at zero";
  EXPECT_GE(stats.held_at_zero, 1);
  // The rest still agree: the step is gone, within the solver's tolerance.
  EXPECT_LT(std::abs(s.step()), 0.01f) << "t0 " << s.at(0) << " t3 " << s.at(3);
  EXPECT_GT(s.at(3), 0.0f) << "the dark side came up to meet the bright one";
}

TEST(LightmapStitch, NothingHeldWhenNothingGoesNegative) {
  // Both sides lit: the unconstrained solution is positive and the stitch is the plain
  // least-squares one (no held texel, one solve).
  OneSeam s(10.0f, 8.0f, 7.0f);
  const bake::SeamStitchStats stats = bake::stitch_seams(s.seams, s.raster, s.layers);
  EXPECT_EQ(stats.held_at_zero, 0);
  EXPECT_EQ(stats.held_at_zero_rounds, 0);
  EXPECT_LT(std::abs(s.step()), 0.01f);
  for (int x = 0; x < 4; ++x) EXPECT_GE(s.at(x), 0.0f);
}

}  // namespace
}  // namespace illum
