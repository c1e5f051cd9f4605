// One exposure story for offline and real-time images, through the real program: a
// light-mapped real-time frame's linear mean is within 10 % of the path tracer's (same
// scene, camera and size), and the default exposures of the two (core/auto_exposure.h's
// rule; the GPU's equals core's within a bin, RealtimeTest.GpuAutoExposureIsCoresRule) are
// within a third of a stop — each tolerance widened by the path tracer's own noise at the
// samples used, estimated from two seeds; and the default 8-bit images of both programs
// agree as far as those allow.
#include <cmath>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "cli_fixture.h"
#include "illum/core/auto_exposure.h"
#include "illum/core/color.h"
#include "illum/core/image.h"
#include "test_support/prerequisites.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;

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
