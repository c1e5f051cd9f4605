// What `illum render` writes, checked through the real program: the EXR + tone-mapped PNG
// pair (both or neither, the PNG exactly the documented tone mapping of the EXR), the
// `--time` budget's overrun, and the same bytes for any `--threads`.
#include <algorithm>
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "illum/core/auto_exposure.h"
#include "illum/core/image.h"

using namespace illum_cli_test;

namespace {

// The "render 0.51s" figure of illum render's summary line, in seconds (−1 if absent).
double render_seconds(const Result& r) {
  std::smatch m;
  const std::regex pattern("render ([0-9]+\\.[0-9]+)s");
  return std::regex_search(r.err, m, pattern) ? std::stod(m[1].str()) : -1.0;
}

int files_in(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.path().filename() != "stdout.txt" && e.path().filename() != "stderr.txt";
  return n;
}

// The tone mapping `illum render` documents for its 8-bit output (--help, core/tonemap.h),
// written out here independently: exposure, then clamp, Reinhard on Rec.709 luminance
// c/(1 + L) clamped, or ACES (Narkowicz's fit), then the sRGB transfer function
// (IEC 61966-2-1) and rounding to 8 bits.
enum class Mapper { kClamp, kReinhard, kAces };
double srgb(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}
std::vector<double> documented_png(const double rgb[3], Mapper mapper, double exposure) {
  double c[3] = {rgb[0] * exposure, rgb[1] * exposure, rgb[2] * exposure};
  if (mapper == Mapper::kReinhard) {
    const double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    for (double& v : c) v = l > 0.0 ? v / (1.0 + l) : 0.0;
  } else if (mapper == Mapper::kAces) {
    for (double& v : c) v = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14);
  }
  std::vector<double> codes(3);
  for (int k = 0; k < 3; ++k) codes[static_cast<size_t>(k)] = std::floor(srgb(c[k]) * 255.0 + 0.5);
  return codes;
}

// The interval of floats that round to the half-float `h` (EXR output is half): ±half its
// spacing (the spacing above h, conservative just above a power of two), widened by a
// float's relative precision so that the reference's double arithmetic cannot miss a code
// the renderer's float arithmetic reaches.
std::pair<double, double> half_interval(double h) {
  const double a = std::abs(h);
  const double spacing = a < 0x1p-14 ? 0x1p-24 : std::ldexp(1.0, std::ilogb(a) - 10);
  const double slack = 0.5 * spacing + 1e-6 * a;
  return {h - slack, h + slack};
}

// Every PNG code must be one the documented mapping gives for some float inside the EXR
// pixel's rounding box and some exposure in [exposure_lo, exposure_hi]. Each tone mapper is
// monotone in each channel and in the exposure, so the extremes of a channel's code over the
// box lie at its corners.
void expect_png_is_tone_mapped_exr(const fs::path& exr_path, const fs::path& png_path,
                                   Mapper mapper, double exposure_lo, double exposure_hi) {
  const illum::Image exr = illum::read_image(exr_path.string());
  const illum::Image png = illum::read_image(png_path.string(), /*srgb=*/false);
  ASSERT_EQ(exr.width(), png.width());
  ASSERT_EQ(exr.height(), png.height());
  ASSERT_GE(png.channels(), 3);
  int mismatches = 0, distinct_codes = 0;
  std::vector<bool> seen(256, false);
  for (int y = 0; y < exr.height(); ++y)
    for (int x = 0; x < exr.width(); ++x) {
      std::pair<double, double> box[3];
      for (int c = 0; c < 3; ++c) box[c] = half_interval(exr.pixel(x, y)[c]);
      double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
      for (int corner = 0; corner < 8; ++corner) {
        const double rgb[3] = {corner & 1 ? box[0].second : box[0].first,
                               corner & 2 ? box[1].second : box[1].first,
                               corner & 4 ? box[2].second : box[2].first};
        for (double exposure : {exposure_lo, exposure_hi}) {
          const std::vector<double> codes = documented_png(rgb, mapper, exposure);
          for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], codes[static_cast<size_t>(c)]);
            hi[c] = std::max(hi[c], codes[static_cast<size_t>(c)]);
          }
        }
      }
      for (int c = 0; c < 3; ++c) {
        const double code = std::round(png.pixel(x, y)[c] * 255.0);
        if (!seen[static_cast<size_t>(code)]) ++distinct_codes;
        seen[static_cast<size_t>(code)] = true;
        if (code < lo[c] || code > hi[c]) {
          if (++mismatches <= 5)
            ADD_FAILURE() << png_path.filename() << " pixel " << x << "," << y << " channel " << c
                          << ": code " << code << ", the EXR's " << exr.pixel(x, y)[c]
                          << " maps to " << lo[c] << ".." << hi[c];
        }
      }
    }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(distinct_codes, 20) << "the image should span many codes for this check to mean much";
}

TEST_F(CliTest, ExrComesWithItsToneMappedPng) {
  // README: `-o x.exr` writes the linear x.exr and a tone-mapped x.png beside it — with the
  // default mapping (ACES, the auto exposure of core/auto_exposure.h) and with the options.
  const fs::path exr = dir_ / "pair.exr", png = dir_ / "pair.png";
  const std::string base =
      "render cornell -i path --width 24 --height 24 --spp 4 -o " + exr.string();
  auto r = run(base);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(exr));
  ASSERT_TRUE(fs::exists(png));
  EXPECT_EQ(files_in(dir_), 2) << "the pair and nothing else (no temporary files)";
  // The rule's exposure from the half-float EXR: each pixel whose rounding box spans a bin
  // edge may have been counted in the neighbouring bin from the float image, moving the mean
  // by at most a bin over the band's pixels.
  const illum::Image linear = illum::read_image(exr.string());
  const illum::AutoExposure auto_exposure = illum::auto_exposure(linear);
  ASSERT_GT(auto_exposure.counted, 24u * 24 / 2);
  int straddling = 0;
  for (int y = 0; y < linear.height(); ++y)
    for (int x = 0; x < linear.width(); ++x) {
      double l[2] = {0.0, 0.0};
      const double weights[3] = {0.2126, 0.7152, 0.0722};
      for (int c = 0; c < 3; ++c) {
        const auto [lo, hi] = half_interval(linear.pixel(x, y)[c]);
        l[0] += weights[c] * lo;
        l[1] += weights[c] * hi;
      }
      straddling += illum::exposure_bin(float(l[0])) != illum::exposure_bin(float(l[1]));
    }
  const double band = illum::exposure::kHighPercentile - illum::exposure::kLowPercentile;
  const double slack = std::exp2(
      illum::kExposureBinWidth * straddling / (band * double(auto_exposure.counted)) + 1e-5);
  expect_png_is_tone_mapped_exr(exr, png, Mapper::kAces, auto_exposure.exposure / slack,
                                auto_exposure.exposure * slack);
  // --exposure multiplies the auto exposure; --fixed-exposure makes it the whole exposure.
  r = run(base + " --tonemap reinhard --exposure 2.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_png_is_tone_mapped_exr(exr, png, Mapper::kReinhard, 2.5 * auto_exposure.exposure / slack,
                                2.5 * auto_exposure.exposure * slack);
  r = run(base + " --tonemap clamp --fixed-exposure");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_png_is_tone_mapped_exr(exr, png, Mapper::kClamp, 1.0, 1.0);
  r = run(base + " --tonemap reinhard --exposure 2.5 --fixed-exposure");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_png_is_tone_mapped_exr(exr, png, Mapper::kReinhard, 2.5, 2.5);
  // --no-preview: the EXR alone.
  fs::remove(png);
  ASSERT_EQ(run(base + " --no-preview").exit_code, 0);
  EXPECT_TRUE(fs::exists(exr));
  EXPECT_FALSE(fs::exists(png));
}

TEST_F(CliTest, FailedExrPngPairLeavesNeither) {
  const fs::path exr = dir_ / "pair.exr", png = dir_ / "pair.png";
  // Bad input: refused before any work.
  expect_bad_input(run("render cornell -i path --spp 0 -o " + exr.string()), "spp");
  expect_bad_input(run("render cornell -i path -p max_bounce=2 -o " + exr.string()), "max_bounce");
  EXPECT_EQ(files_in(dir_), 0);
  // The preview's name is taken by a folder: refused before the render, naming it.
  fs::create_directories(png);
  expect_bad_input(run("render cornell -i ao --width 8 --height 8 --spp 1 -o " + exr.string()),
                   "pair.png");
  EXPECT_FALSE(fs::exists(exr));
  fs::remove(png);
  // The folder appears while the render runs: the EXR is written first, the preview then
  // fails, and the EXR must go too.
  const std::string cmd = "sh -c '" + std::string(ILLUM_BINARY_DIR) +
                          "/bin/illum render cornell -i path --width 16 --height 16 --spp 100000 "
                          "--time 1.5 -o " +
                          exr.string() + " 2>" + (dir_ / "stderr.txt").string() +
                          " & pid=$!; sleep 0.5; mkdir " + png.string() + "; wait $pid'";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2) << slurp(dir_ / "stderr.txt");
  EXPECT_NE(slurp(dir_ / "stderr.txt").find("pair.png"), std::string::npos);
  EXPECT_FALSE(fs::exists(exr)) << "a failed preview must not leave the EXR";
  EXPECT_EQ(files_in(dir_), 1) << "only the folder the test made";
}

TEST_F(CliTest, TimeBudgetOverrunsByAtMostOnePass) {
  // render/README.md: --time stops the render after the first pass that ends past the
  // budget. The reported render time must therefore lie between the budget and the budget
  // plus one pass of at most 16 spp and the integrator's setup. A run of 32 spp (passes 1,
  // 1, 2, 4, 8, 16) does that setup and a whole 16-spp pass and more, so its render time,
  // taken before and after under the same load, bounds the overrun; the summary line
  // rounds each figure to 0.01 s. One thread, so the figures do not depend on scheduling.
  // 8192 spp cannot finish in the budget (about 30M rays on one thread), so only the
  // budget can stop the render.
  const double budget = 0.5;
  const std::string common =
      "render cornell -i path --width 32 --height 32 --threads 1 -o " + (dir_ / "t.png").string();
  const Result before = run(common + " --spp 32");
  const Result timed = run(common + " --spp 8192 --time " + std::to_string(budget));
  const Result after = run(common + " --spp 32");
  ASSERT_EQ(timed.exit_code, 0) << timed.err;
  const double pass = std::max(render_seconds(before), render_seconds(after));
  const double seconds = render_seconds(timed);
  ASSERT_GT(pass, 0.0) << before.err;
  std::printf("budget %.2f s: render %.2f s; a 32-spp render takes %.2f s\n", budget, seconds,
              pass);
  EXPECT_GE(seconds, budget - 0.005);
  EXPECT_LE(seconds, budget + pass + 0.01) << timed.err;
}

TEST_F(CliTest, SameBytesForAnyThreadCount) {
  // render/README.md: the same seed gives the same image for any thread count (on fewer
  // cores than asked for, as many threads run as there are).
  std::string first;
  for (const std::string threads : {"1", "2", "4"}) {
    const fs::path out = dir_ / fs::path("t" + threads + ".exr");
    const auto r = run("render cornell -i path --width 40 --height 24 --spp 4 --seed 9 --threads " +
                       threads + " --no-preview -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string bytes = slurp(out);
    ASSERT_FALSE(bytes.empty());
    if (threads == "1") {
      first = bytes;
    } else {
      EXPECT_TRUE(bytes == first) << threads << " threads wrote other bytes than 1 thread";
    }
  }
}

}  // namespace

// Baking over an earlier bake folder replaces it, but never deletes a file no bake wrote:
// a folder holding one is refused with one line before any work, left as it was. Light-map,
// PRT and probe folders alike (one check: baked/lightmap_file.h check_bake_output).
TEST_F(CliTest, BakeOverAFolderKeepsFilesItDidNotWrite) {
  const std::vector<std::pair<std::string, std::string>> kinds = {
      {"--resolution 32 --spp 1", "lightmap.json"},
      {"--kind prt --resolution 32 --spp 1", "prt.json"},
      {"--kind probes --spp 1", "probes.json"}};
  for (const auto& [options, manifest] : kinds) {
    const fs::path folder = dir_ / "baked";
    fs::remove_all(folder);
    const std::string bake = "bake cornell " + options + " -o " + folder.string();
    ASSERT_EQ(run(bake).exit_code, 0) << options;
    EXPECT_EQ(run(bake).exit_code, 0) << options << ": an earlier bake is replaced";
    write("baked/notes.txt", "mine");
    const Result r = run(bake);
    EXPECT_EQ(r.exit_code, 2) << options << ": " << r.err;
    EXPECT_EQ(r.err_lines(), 1) << r.err;
    EXPECT_NE(r.err.find("notes.txt"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(folder / "notes.txt"), "mine");
    EXPECT_TRUE(fs::exists(folder / manifest)) << options;
  }
}
