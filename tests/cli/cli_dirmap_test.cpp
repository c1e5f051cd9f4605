// `illum bake --basis dominant` and its display (issue 12 part 3), and seam stitching's
// switch (part 4), end to end: the folder's three layers reproduce the plain map of the
// same scene on the baked normal; a real-time frame of Cornell from the dominant folder
// (lavapipe, validation layers on) against the frame from the plain folder; bad options
// refused with one line, exit 2.
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "illum/core/image.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;
using illum_cli_test::slurp;

constexpr double kZ = 5.0;

class DirmapCli : public CliTest {
 protected:
  fs::path bake(const std::string& basis, const std::string& extra = "") {
    const fs::path folder = dir_ / basis;
    const Result r = run("bake cornell --resolution 32 --spp 64 --seed 1 --basis " + basis + " " +
                         extra + " -o " + folder.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return folder;
  }
};

// Per texel of the Cornell light-map, E/π on the baked normal from the dominant layers,
// A + C·d_z, against the plain map: two independent estimates of the same value (cosine
// against mixture sampling), so the mean of the differences over the texels is 0 within
// kZ standard errors of that mean (the texels are independent estimates).
TEST_F(DirmapCli, DominantFolderReproducesThePlainMap) {
  const fs::path dominant = bake("dominant"), plain = bake("plain");
  const nlohmann::json manifest = nlohmann::json::parse(slurp(dominant / "lightmap.json"));
  EXPECT_EQ(manifest["basis"], "dominant");
  ASSERT_EQ(manifest["layers"].size(), 3u);
  // Cornell is boxes only: every chart edge is a crease, where the light may jump, so no
  // edge is a seam to stitch (the smooth-surface cases are in tests/bake, LightmapSeams).
  EXPECT_EQ(manifest["bake"]["seam_edges"], 0);
  const illum::Image a = illum::read_image((dominant / "layer0.exr").string(), false);
  const illum::Image c = illum::read_image((dominant / "layer1.exr").string(), false);
  const illum::Image d = illum::read_image((dominant / "layer2.exr").string(), false);
  const illum::Image p = illum::read_image((plain / "layer0.exr").string(), false);
  double sum = 0, sum2 = 0, plain_sum = 0;
  int n = 0;
  for (int y = 0; y < p.height(); ++y)
    for (int x = 0; x < p.width(); ++x) {
      const double lp = illum::luminance(p.rgb(x, y));
      if (!(lp > 0.0)) continue;  // outside every chart and its gutter
      const illum::Color dir = d.rgb(x, y);
      EXPECT_NEAR(glm::length(dir), 1.0f, 2e-3f) << "direction not unit at " << x << "," << y;
      const double e0 = illum::luminance(a.rgb(x, y) + c.rgb(x, y) * dir.z);
      sum += e0 - lp;
      sum2 += (e0 - lp) * (e0 - lp);
      plain_sum += lp;
      ++n;
    }
  ASSERT_GT(n, 100);
  const double mean = sum / n, sd = std::sqrt(std::max(sum2 / n - mean * mean, 0.0));
  std::printf("dominant vs plain: %d texels, mean difference %.5f (se %.5f), plain mean %.4f\n", n,
              mean, sd / std::sqrt(n - 1.0), plain_sum / n);
  EXPECT_LE(std::abs(mean), kZ * sd / std::sqrt(n - 1.0));

#ifdef ILLUM_HAVE_GPU
  // The frames, validation layers on. Each pixel shows albedo × a bilinear blend of texels,
  // the same albedo and weights in both frames, so the relative difference of the frames'
  // sums is a weighted mean of the texels' differences (weights ≥ 0, summing to 1) divided
  // by the plain map's like mean: its noise is at most the texels' own spread (the weights'
  // Σw² ≤ 1), so kZ·sd/mean bounds it — loose, but a wrong display (a wrong layer, the
  // direction's frame, a missing d_z) is off by far more (the ambient alone is 0 on texels
  // lit by the area light only).
  setenv("ILLUM_VULKAN_VALIDATION", "1", 1);  // the frames' children inherit it
  const fs::path fa = dir_ / "dominant.exr", fb = dir_ / "plain.exr";
  for (const auto& [folder, out] : {std::pair{dominant, fa}, std::pair{plain, fb}}) {
    const fs::path json = out.string() + ".json";
    const Result r = run("frame cornell --baked " + folder.string() +
                         " --width 64 --height 64 --json " + json.string() + " -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(json))["validation_messages"], 0) << r.err;
  }
  const illum::Image ia = illum::read_image(fa.string(), false);
  const illum::Image ib = illum::read_image(fb.string(), false);
  double frame_a = 0, frame_b = 0;
  for (int y = 0; y < ia.height(); ++y)
    for (int x = 0; x < ia.width(); ++x) {
      frame_a += illum::luminance(ia.rgb(x, y));
      frame_b += illum::luminance(ib.rgb(x, y));
    }
  ASSERT_GT(frame_b, 0.0);
  const double relative = (frame_a - frame_b) / frame_b;
  std::printf("frames: dominant / plain − 1 = %.5f (bound %.5f)\n", relative,
              kZ * sd / (plain_sum / n));
  EXPECT_LE(std::abs(relative), kZ * sd / (plain_sum / n));
#endif
}

// Stitching is on by default and recorded; -p stitch=false turns it off.
TEST_F(DirmapCli, StitchingCanBeTurnedOff) {
  const fs::path off = bake("plain", "-p stitch=false");
  const nlohmann::json manifest = nlohmann::json::parse(slurp(off / "lightmap.json"));
  EXPECT_EQ(manifest["bake"]["stitch"], false);
  EXPECT_EQ(manifest["bake"]["seam_edges"], 0);
}

TEST_F(DirmapCli, BadOptionsAreRefused) {
  const fs::path out = dir_ / "bad";
  expect_bad_input(run("bake cornell --basis dominantt -o " + out.string()), "basis");
  expect_bad_input(run("bake cornell -p stitch=maybe -o " + out.string()), "stitch");
  expect_bad_input(run("bake cornell --method radiosity --basis sh2 -o " + out.string()), "basis");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
