// `illum bake --basis dominant` and its display, and seam stitching (its switch, and no
// negative texel on Sibenik), end to end: the folder's three layers reproduce the plain map of the
// same scene on the baked normal; a real-time frame of Cornell from the dominant folder
// (lavapipe, validation layers on) against the frame from the plain folder; bad options
// refused with one line, exit 2.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "illum/core/image.h"
#include "test_support/prerequisites.h"

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
  // The display: a frame from the dominant folder against a frame from a plain folder made
  // of that same folder's A + C·d_z (same atlas, manifest basis "plain"), validation layers
  // on. Cornell has no normal maps, so every pixel shows albedo × the bilinear blend of
  // A + C·d_z over the texels... but for the blend of a product: per channel the frames
  // differ by albedo × Cov_w(C, d_z) over the four texels' weights, at most
  // ¼·range(C)·range(d_z) of the 2×2 block (|albedo| ≤ 1); plus half-float rounding of
  // the stored layers and of the two frames' RGBA16F targets, 2⁻¹¹ relative each, counted
  // as 4·2⁻¹¹ of the larger pixel. The bound is the largest block's, over all blocks.
  const illum::Image derived_layer = [&] {
    illum::Image e0(p.width(), p.height(), 3);
    for (int y = 0; y < p.height(); ++y)
      for (int x = 0; x < p.width(); ++x)
        e0.set_rgb(x, y, a.rgb(x, y) + c.rgb(x, y) * d.rgb(x, y).z);
    return e0;
  }();
  const fs::path derived = dir_ / "derived";
  fs::copy(dominant, derived, fs::copy_options::recursive);
  illum::write_image((derived / "layer0.exr").string(), derived_layer);
  nlohmann::json derived_manifest = manifest;
  derived_manifest["basis"] = "plain";
  derived_manifest["layers"] = {"layer0.exr"};
  std::ofstream(derived / "lightmap.json") << derived_manifest.dump(2);
  double covariance_bound = 0.0;
  for (int y = 0; y + 1 < p.height(); ++y)
    for (int x = 0; x + 1 < p.width(); ++x)
      for (int ch = 0; ch < 3; ++ch) {
        float c_lo = 1e30f, c_hi = -1e30f, z_lo = 1e30f, z_hi = -1e30f;
        for (int k = 0; k < 4; ++k) {
          const int tx = x + (k & 1), ty = y + (k >> 1);
          c_lo = std::min(c_lo, c.rgb(tx, ty)[ch]);
          c_hi = std::max(c_hi, c.rgb(tx, ty)[ch]);
          z_lo = std::min(z_lo, d.rgb(tx, ty).z);
          z_hi = std::max(z_hi, d.rgb(tx, ty).z);
        }
        covariance_bound = std::max(covariance_bound, 0.25 * (c_hi - c_lo) * (z_hi - z_lo));
      }

  setenv("ILLUM_VULKAN_VALIDATION", "1", 1);  // the frames' children inherit it
  const fs::path fa = dir_ / "dominant.exr", fb = dir_ / "derived.exr", fc = dir_ / "plain.exr";
  for (const auto& [folder, out] :
       {std::pair{dominant, fa}, std::pair{derived, fb}, std::pair{plain, fc}}) {
    const fs::path json = out.string() + ".json";
    const Result r = run("frame cornell --baked " + folder.string() +
                         " --width 64 --height 64 --json " + json.string() + " -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(json))["validation_messages"], 0) << r.err;
  }
  const illum::Image ia = illum::read_image(fa.string(), false);
  const illum::Image ib = illum::read_image(fb.string(), false);
  const illum::Image ic = illum::read_image(fc.string(), false);
  double worst = 0.0, frame_a = 0.0, frame_c = 0.0;
  int over = 0;
  for (int y = 0; y < ia.height(); ++y)
    for (int x = 0; x < ia.width(); ++x) {
      for (int ch = 0; ch < 3; ++ch) {
        const double va = ia.rgb(x, y)[ch], vb = ib.rgb(x, y)[ch];
        const double bound = covariance_bound + 4.0 * std::ldexp(std::max(va, vb), -11);
        worst = std::max(worst, std::abs(va - vb));
        over += std::abs(va - vb) > bound;
      }
      frame_a += illum::luminance(ia.rgb(x, y));
      frame_c += illum::luminance(ic.rgb(x, y));
    }
  std::printf(
      "frames: dominant vs its own A + C·d_z as plain: worst |difference| %.5f, covariance "
      "bound %.5f, %d values over; dominant / plain-baked frame − 1 = %.5f\n",
      worst, covariance_bound, over, frame_a / frame_c - 1.0);
  EXPECT_EQ(over, 0);
#endif
}

// Stitching is on by default and recorded; -p stitch=false turns it off.
TEST_F(DirmapCli, StitchingCanBeTurnedOff) {
  const fs::path off = bake("plain", "-p stitch=false");
  const nlohmann::json manifest = nlohmann::json::parse(slurp(off / "lightmap.json"));
  EXPECT_EQ(manifest["bake"]["stitch"], false);
  EXPECT_EQ(manifest["bake"]["seam_edges"], 0);
}

// Stitching never makes light negative: Sibenik at 512², 16 spp, has seams between bright
// and dark charts everywhere (0.6 % of its texels went below zero before the solve held
// them at zero); every channel of every texel of the stitched map is ≥ 0.
TEST_F(DirmapCli, StitchedSibenikHasNoNegativeTexel) {
  ILLUM_REQUIRE_SHARED_SCENE("sibenik/sibenik.obj");
  const fs::path folder = dir_ / "sibenik";
  const Result r = run("bake sibenik --resolution 512 --spp 16 --seed 1 -o " + folder.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json manifest = nlohmann::json::parse(slurp(folder / "lightmap.json"));
  EXPECT_GT(manifest["bake"]["seam_edges"].get<int>(), 1000);
  const illum::Image map = illum::read_image((folder / "layer0.exr").string());
  int64_t negative = 0;
  float lowest = 0.0f;
  for (float v : map.data()) {
    negative += v < 0.0f;
    lowest = std::min(lowest, v);
  }
  EXPECT_EQ(negative, 0) << "lowest " << lowest;
}

// The PRT bake moves texel samples out of geometry as the light-map bake does: Cornell's
// floor runs on under both blocks, so some of its texel centres lie under them.
TEST_F(DirmapCli, PrtBakePushesTexelsOutOfGeometry) {
  const fs::path prt = dir_ / "prt";
  const Result r =
      run("bake cornell --kind prt --resolution 32 --spp 4 --bands 2 --seed 1 -o " + prt.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json manifest = nlohmann::json::parse(slurp(prt / "prt.json"));
  EXPECT_GT(manifest["bake"]["texels_pushed_out"].get<int>() +
                manifest["bake"]["texels_rejected"].get<int>(),
            0);
}

TEST_F(DirmapCli, BadOptionsAreRefused) {
  const fs::path out = dir_ / "bad";
  expect_bad_input(run("bake cornell --basis dominantt -o " + out.string()), "basis");
  expect_bad_input(run("bake cornell -p stitch=maybe -o " + out.string()), "stitch");
  expect_bad_input(run("bake cornell --method radiosity --basis sh2 -o " + out.string()), "basis");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
