// One exposure story for offline and real-time images, through the real program: a
// light-mapped real-time frame's linear mean is within 10 % of the path tracer's (same
// scene, camera and size), and the default exposures of the two (core/auto_exposure.h's
// rule; the GPU's equals core's within a bin, RealtimeTest.GpuAutoExposureIsCoresRule) are
// within a third of a stop — each tolerance widened by the path tracer's own noise at the
// samples used, estimated from two seeds; and the default 8-bit images of both programs
// agree as far as those allow.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "cli_fixture.h"
#include "illum/core/auto_exposure.h"
#include "illum/core/color.h"
#include "illum/core/image.h"
#include "illum/core/tonemap.h"
#include "test_support/prerequisites.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;

// The command line of `illum ARGS`, for CliTest::run_command: CliTest::run's std::string +
// chain, inlined here, draws a false -Warray-bounds from GCC 12 at -O1 with the precompiled
// headers.
std::string illum_line(const std::string& args) {
  return fmt::format("{}/bin/illum {}", ILLUM_BINARY_DIR, args);
}

// The largest difference, in 8-bit codes, between `png` and `mapper`(`exr` × exposure) sRGB
// encoded (the reference in doubles through core's tone mapper, which
// RealtimeTest.CpuToneMappersMatchTheGpuPass holds to the GPU pass).
double worst_code_difference(const illum::Image& exr, const illum::Image& png,
                             illum::ToneMapper mapper, float exposure) {
  double worst = 0.0;
  for (int y = 0; y < exr.height(); ++y)
    for (int x = 0; x < exr.width(); ++x) {
      const illum::Color want = illum::tone_map(exr.rgb(x, y) * exposure, mapper);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(255.0 * illum::srgb_encode(want[c]) -
                                         std::round(255.0 * png.pixel(x, y)[c])));
    }
  return worst;
}

// `illum relight` makes its 8-bit image as `illum render` does: ACES at the auto exposure by
// default, --exposure a multiplier on it, --fixed-exposure the whole exposure.
TEST_F(CliTest, RelightPngIsExposedAsRenderIs) {
  const fs::path prt = dir_ / "prt", exr = dir_ / "relit.exr", png = dir_ / "relit.png";
  const Result baked = run_command(illum_line(fmt::format(
      "bake cornell --kind prt --resolution 32 --spp 4 --bands 3 --seed 1 -o {}", prt.string())));
  ASSERT_EQ(baked.exit_code, 0) << baked.err;
  const auto relight = [&](const std::string& options, const fs::path& out) {
    return run_command(illum_line(fmt::format(
        "relight cornell --baked {} --sun 0.3,-1,-0.5,2 --width 24 --height 24 {} -o {}",
        prt.string(), options, out.string())));
  };
  ASSERT_EQ(relight("", exr).exit_code, 0);
  const illum::Image linear = illum::read_image(exr.string());
  const float e = illum::auto_exposure(linear).exposure;
  ASSERT_GT(illum::auto_exposure(linear).counted, 24u * 24 / 4);
  const struct {
    std::string options;
    illum::ToneMapper mapper;
    float exposure;
  } cases[] = {{"", illum::ToneMapper::kAces, e},
               {"--exposure 2", illum::ToneMapper::kAces, 2.0f * e},
               {"--tonemap clamp --fixed-exposure --exposure 0.5", illum::ToneMapper::kClamp, 0.5f},
               {"--fixed-exposure", illum::ToneMapper::kAces, 1.0f}};
  for (const auto& c : cases) {
    ASSERT_EQ(relight(c.options, png).exit_code, 0) << c.options;
    // The EXR is half floats: one code of rounding either way, and one for the exposure the
    // half image gives against the float image's.
    EXPECT_LE(
        worst_code_difference(linear, illum::read_image(png.string(), false), c.mapper, c.exposure),
        2.0)
        << c.options;
  }
}

// Normals, albedo, depth and AO are not radiance: their PNG is the values as they are
// (clamp, exposure 1) unless a tone mapper is named.
TEST_F(CliTest, NonRadianceViewsAreShownAsTheyAre) {
  const fs::path exr = dir_ / "ao.exr", png = dir_ / "ao.png";
  ASSERT_EQ(run_command(illum_line("render cornell -i ao --width 24 --height 24 --spp 2 -o " +
                                   exr.string()))
                .exit_code,
            0);
  const illum::Image linear = illum::read_image(exr.string());
  EXPECT_LE(worst_code_difference(linear, illum::read_image(png.string(), false),
                                  illum::ToneMapper::kClamp, 1.0f),
            1.0);
  // The same image through the radiance defaults would differ: the check can fail.
  EXPECT_GT(worst_code_difference(linear, illum::read_image(png.string(), false),
                                  illum::ToneMapper::kAces, illum::auto_exposure(linear).exposure),
            10.0);
}

#ifdef ILLUM_HAVE_GPU

double mean_luminance(const illum::Image& img) {
  double sum = 0.0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) sum += illum::luminance(img.rgb(x, y));
  return sum / double(img.pixel_count());
}

class ExposureAgreement : public CliTest {
 protected:
  // CliTest::run through fmt: GCC 12 at -O1 warns falsely (-Warray-bounds) on run()'s
  // std::string + chain inlined here once the headers come precompiled.
  Result illum(const std::string& args) {
    return run_command(fmt::format("{}/bin/illum {}", ILLUM_BINARY_DIR, args));
  }

  // Bakes `scene` (all light), renders its light-mapped frame and two path-traced images
  // (seeds 1, 2) at width × height, and checks the means and the default exposures. With
  // `glb`, the frame is of the scene exported with its light-map (`illum export`, RGBM in the
  // .glb) rather than of the bake folder.
  void check(const std::string& scene, const std::string& bake_options, int width, int height,
             int spp, bool glb = false) {
    const fs::path lm = dir_ / "lm", frame = dir_ / "frame.exr";
    const std::string size = fmt::format(" --width {} --height {}", width, height);
    Result r = illum(fmt::format("bake {} --seed 1 {} -o {}", scene, bake_options, lm.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string shown = fmt::format("{} --baked {}", scene, lm.string());
    if (glb) {
      const fs::path exported = dir_ / "exported.glb";
      r = illum(fmt::format("export {} --baked {} -o {}", scene, lm.string(), exported.string()));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      shown = exported.string();  // its light-map is embedded
    }
    r = illum(fmt::format("frame {}{} -o {}", shown, size, frame.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const fs::path frame_png = dir_ / "frame.png";
    r = illum(fmt::format("frame {}{} -o {}", shown, size, frame_png.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    illum::Image path[2];
    for (int seed : {1, 2}) {
      const fs::path out = dir_ / fmt::format("path{}.exr", seed);
      r = illum(fmt::format("render {} -i path{} --spp {} --seed {} -o {}", scene, size, spp, seed,
                            out.string()));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      path[seed - 1] = illum::read_image(out.string());
    }
    const illum::Image realtime = illum::read_image(frame.string());
    ASSERT_EQ(realtime.width(), width);

    // Noise of the path tracer's mean: per-pixel noise is independent between seeds, so the
    // difference image's variance is twice a pixel's; the mean of both images has
    // σ² = var(pixel) / (2 N).
    const size_t n = realtime.pixel_count();
    const double m1 = mean_luminance(path[0]), m2 = mean_luminance(path[1]);
    double var = 0.0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double d = illum::luminance(path[0].rgb(x, y)) - illum::luminance(path[1].rgb(x, y));
        var += (d - (m1 - m2)) * (d - (m1 - m2));
      }
    var /= 2.0 * double(n - 1);
    const double path_mean = 0.5 * (m1 + m2), sigma = std::sqrt(var / (2.0 * double(n)));
    const double frame_mean = mean_luminance(realtime);
    std::printf("%s: frame mean %.5f, path mean %.5f ± %.5f (1σ): %+.1f %%\n", scene.c_str(),
                frame_mean, path_mean, sigma, 100.0 * (frame_mean / path_mean - 1.0));
    EXPECT_LT(3.0 * sigma, 0.03 * path_mean) << "too noisy a reference for a 10 % check";
    EXPECT_LE(std::abs(frame_mean - path_mean), 0.10 * path_mean + 3.0 * sigma);

    // Default exposures: the offline image's is the rule on the path-traced image, the
    // frame's the rule on the frame. The path tracer's noise moves its exposure by about the
    // two seeds' difference.
    const double e1 = illum::auto_exposure(path[0]).exposure;
    const double e2 = illum::auto_exposure(path[1]).exposure;
    const double e_frame = illum::auto_exposure(realtime).exposure;
    const double stops = std::log2(e_frame / std::sqrt(e1 * e2));
    const double noise = std::abs(std::log2(e1 / e2));
    std::printf("%s: exposure frame %.4f, path %.4f / %.4f: %+.3f stops (noise %.3f)\n",
                scene.c_str(), e_frame, e1, e2, stops, noise);
    EXPECT_LE(std::abs(stops), 1.0 / 3.0 + noise);

    // What a user sees: the default 8-bit images (ACES of HDR × exposure, each program's own
    // exposure) have mean display values no further apart than the linear means and the
    // exposures allow (ACES compresses, so the ratio of display means is within theirs).
    const double shown_path = mean_luminance(illum::read_image((dir_ / "path1.png").string()));
    const double shown_frame = mean_luminance(illum::read_image(frame_png.string()));
    const double allowed = std::log2(1.10 + 3.0 * sigma / path_mean) + 1.0 / 3.0 + noise;
    std::printf("%s: display mean frame %.4f, path %.4f: %+.3f stops (allowed %.3f)\n",
                scene.c_str(), shown_frame, shown_path, std::log2(shown_frame / shown_path),
                allowed);
    EXPECT_LE(std::abs(std::log2(shown_frame / shown_path)), allowed);
  }
};

TEST_F(ExposureAgreement, CornellLightmapFrameAndPathTracer) {
  check("cornell", "--resolution 128 --spp 128", 64, 64, 64);
}

TEST_F(ExposureAgreement, ExportedCornellGlbFrameAndPathTracer) {
  check("cornell", "--resolution 128 --spp 128", 64, 64, 64, /*glb=*/true);
}

TEST_F(ExposureAgreement, SibenikLightmapFrameAndPathTracer) {
  ILLUM_REQUIRE_SHARED_SCENE("sibenik/sibenik.obj");
  check("sibenik", "--resolution 512 --spp 32", 96, 64, 32);
}

#endif

}  // namespace
