// `illum view` for real: the window, swapchain and ImGui panel under Xvfb on lavapipe with
// the validation layer, compared with the headless `illum frame` output of the same scene.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "illum/core/image.h"

namespace fs = std::filesystem;

namespace {

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  for (std::string dir; std::getline(ss, dir, ':');)
    if (!dir.empty() && fs::exists(fs::path(dir) / program)) return true;
  return false;
}

class ViewerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("illum-view-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `prefix` goes before the program (environment, xvfb-run).
  Outcome run(const std::string& prefix, const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = prefix + " " + std::string(ILLUM_BINARY_DIR) + "/bin/illum " + args +
                            " >" + out.string() + " 2>" + err.string() + " </dev/null";
    const int status = std::system(cmd.c_str());
    Outcome r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  fs::path dir_;
};

constexpr int kWidth = 320, kHeight = 240;

TEST_F(ViewerTest, WindowShowsSceneAndPanelWithoutValidationMessages) {
  if (!on_path("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/install-deps.sh)";
  const fs::path shot = dir_ / "shot.png", ref = dir_ / "ref.png";
  const std::string size =
      " --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight);
  // Frame 1 lays the panel out, frame 2 draws it at its final size; 4 leaves margin.
  const Outcome view = run("ILLUM_VULKAN_VALIDATION=1 xvfb-run -a -s '-screen 0 640x480x24'",
                           "view cornell" + size + " --frames 4 --screenshot " + shot.string());
  ASSERT_EQ(view.exit_code, 0) << view.out << view.err;
  // The headless fallback message would mean no window was opened.
  EXPECT_EQ(view.err.find("no window available"), std::string::npos) << view.err;
  EXPECT_EQ(view.err.find("alidation"), std::string::npos) << view.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      view.out, m,
      std::regex(
          R"(4 frames, (\d+)x(\d+), panel at (-?\d+),(-?\d+) size (\d+)x(\d+), (\d+) validation messages)")))
      << view.out;
  EXPECT_EQ(std::stoi(m[1]), kWidth);
  EXPECT_EQ(std::stoi(m[2]), kHeight);
  EXPECT_EQ(std::stoi(m[7]), 0) << "validation messages:\n" << view.err;
  const int px = std::stoi(m[3]), py = std::stoi(m[4]);
  const int pw = std::stoi(m[5]), ph = std::stoi(m[6]);
  ASSERT_GT(pw, 0);
  ASSERT_GT(ph, 0);

  const Outcome frame =
      run("ILLUM_VULKAN_VALIDATION=1", "frame cornell" + size + " -o " + ref.string());
  ASSERT_EQ(frame.exit_code, 0) << frame.err;
  // Both read code for code (value/255).
  const illum::Image a = illum::read_image(shot.string(), false);
  const illum::Image b = illum::read_image(ref.string(), false);
  ASSERT_EQ(a.width(), kWidth);
  ASSERT_EQ(a.height(), kHeight);
  ASSERT_EQ(b.width(), kWidth);
  ASSERT_EQ(b.height(), kHeight);

  // Same renderer, camera and size, blitted 1:1: the scene outside the panel must match the
  // headless frame to 8-bit rounding (≤ 1 code; allow 2 as the realtime tests do) on all but
  // 1% of pixels. The panel (94% opaque dark background, text, widgets) must change most of
  // the pixels it covers.
  const float tol = 2.0f / 255.0f + 1e-4f;
  long scene_total = 0, scene_match = 0, panel_total = 0, panel_diff = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      float d = 0.0f;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]));
      // One pixel of margin: ImGui's window border is anti-aliased.
      const bool inside = x >= px && x < px + pw && y >= py && y < py + ph;
      const bool outside = x < px - 1 || x > px + pw || y < py - 1 || y > py + ph;
      if (inside) {
        ++panel_total;
        panel_diff += d > tol;
      } else if (outside) {
        ++scene_total;
        scene_match += d <= tol;
      }
    }
  ASSERT_GT(scene_total, kWidth * kHeight / 4) << "the panel covers most of the window";
  const double scene_fraction = static_cast<double>(scene_match) / static_cast<double>(scene_total);
  const double panel_fraction = static_cast<double>(panel_diff) / static_cast<double>(panel_total);
  std::printf("scene region: %.4f of %ld pixels match; panel region: %.4f of %ld pixels differ\n",
              scene_fraction, scene_total, panel_fraction, panel_total);
  EXPECT_GE(scene_fraction, 0.99);
  EXPECT_GE(panel_fraction, 0.5);
  fs::copy_file(shot, fs::path(ILLUM_BINARY_DIR) / "viewer_test_shot.png",
                fs::copy_options::overwrite_existing);
}

TEST_F(ViewerTest, WithoutDisplayFallsBackToOneHeadlessFrame) {
  const fs::path out = dir_ / "fallback.png";
  const Outcome r = run("env -u DISPLAY -u WAYLAND_DISPLAY ILLUM_VULKAN_VALIDATION=1",
                        "view cornell --width 32 --height 32 --fallback-output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("illum view: no window available"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out));
  const illum::Image img = illum::read_image(out.string());
  EXPECT_EQ(img.width(), 32);
}

}  // namespace
