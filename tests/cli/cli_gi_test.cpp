// No hidden amplification: at the default amplification 1, the mean indirect radiance that
// `--enable lpv` adds to a frame of the spot-lit Cornell box is within a stated factor of the
// path tracer's first indirect bounce (`--bounce-mode indirect1`) over the same view — the
// band comes from bench/scripts/gi_vs_path.sh's measurement (docs/realtime-lpv.md,
// "Validation") and the reference's noise, estimated from two seeds. The method's own check:
// at amplification 0 the two frames are the same, so their difference is the LPV's light and
// nothing else.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "cli_fixture.h"
#include "illum/core/image.h"

namespace illum_cli_test {
namespace {

class CliGi : public CliTest {
 protected:
  // Writes `illum ARGS -o NAME.exr` and returns the image.
  illum::Image exr(const std::string& args, const std::string& name) {
    const std::string path = (dir_ / (name + ".exr")).string();
    const Result r = run(args + " -o " + path);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    return r.exit_code == 0 ? illum::read_image(path) : illum::Image();
  }
};

double mean_luminance(const illum::Image& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const illum::Color c = image.rgb(x, y);
      sum += 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    }
  return sum / double(image.width() * image.height());
}

#ifdef ILLUM_HAVE_GPU
constexpr const char* kFrame = "frame cornell-spot --width 64 --height 64 -p ambient=[0,0,0]";

TEST_F(CliGi, LpvMeanIndirectIsWithinItsFactorOfThePathTracers) {
  const illum::Image no_gi = exr(kFrame, "nogi");
  const illum::Image lpv = exr(std::string(kFrame) + " --enable lpv", "lpv");
  const std::string path =
      "render cornell-spot -i path --bounce-mode indirect1 --width 64 --height 64 --spp 64";
  const illum::Image a = exr(path + " --seed 1", "path1"), b = exr(path + " --seed 2", "path2");
  ASSERT_FALSE(HasFailure());
  const double realtime = mean_luminance(lpv) - mean_luminance(no_gi);
  const double reference = (mean_luminance(a) + mean_luminance(b)) / 2.0;
  // The standard error of the two seeds' mean, from their difference (|a − b|/2 estimates σ
  // of the mean of two, taken as the 1-σ of the 64-spp reference).
  const double se = std::abs(mean_luminance(a) - mean_luminance(b)) / 2.0;
  ASSERT_GT(reference, 0.0);
  const double ratio = realtime / reference;
  // The ratio measured at this size and spp (docs/realtime-lpv.md, Validation; the script's
  // 256² run gives nearly the same), and the factor either way that any change of the LPV's
  // light must stay within — a gain or loss of 1.5× or more, hidden or not, fails.
  constexpr double kMeasured = 0.216, kFactor = 1.5;
  constexpr double kLow = kMeasured / kFactor, kHigh = kMeasured * kFactor;
  const double slack = 3.0 * se / reference * kMeasured;
  EXPECT_GE(ratio, kLow - slack) << fmt::format("LPV {:.5f}, path {:.5f} ± {:.5f}", realtime,
                                                reference, se);
  EXPECT_LE(ratio, kHigh + slack) << fmt::format("LPV {:.5f}, path {:.5f} ± {:.5f}", realtime,
                                                 reference, se);
}

TEST_F(CliGi, AtAmplificationZeroTheLpvFrameIsTheFrameWithout) {
  const illum::Image no_gi = exr(kFrame, "nogi");
  const illum::Image zero = exr(std::string(kFrame) + " --enable lpv -p lpv.amplification=0", "z");
  const illum::Image one = exr(std::string(kFrame) + " --enable lpv", "one");
  ASSERT_FALSE(HasFailure());
  double differ = 0.0;
  for (int y = 0; y < no_gi.height(); ++y)
    for (int x = 0; x < no_gi.width(); ++x)
      for (int c = 0; c < 3; ++c) differ += no_gi.rgb(x, y)[c] != zero.rgb(x, y)[c];
  EXPECT_EQ(differ, 0.0);
  // And the comparison can see the LPV's light at all.
  EXPECT_GT(mean_luminance(one), 1.05 * mean_luminance(no_gi));
}
#endif

}  // namespace
}  // namespace illum_cli_test
