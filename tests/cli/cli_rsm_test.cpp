// The `rsm` add-on and the built-in `cornell-spot` scene at the CLI: the scene loads by name in
// the path tracer and the real-time frame, a reflective-shadow-map layer can be shown with
// -p debug.show, and a bad `rsm.lights` is one line with exit code 2 and no output file.
#include <string>

// GCC 12 at -O1 reports false -Warray-bounds / -Wstringop-overflow inside CliTest::run's string
// concatenation once it is inlined here (inlined std::string moves).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Warray-bounds"
#pragma GCC diagnostic ignored "-Wstringop-overflow"
#endif
#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliRsm : public CliTest {};

TEST_F(CliRsm, CornellSpotPathTracesByName) {
  const Result r =
      run("render cornell-spot --bounce-mode indirect1 --spp 1 --width 8 --height 8 -o " +
          (dir_ / "r.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "r.png"));
}

// `illum frame` exists only where the GPU layers are built (not in the asan tree).
#ifdef ILLUM_HAVE_GPU
TEST_F(CliRsm, ShowsAFluxLayer) {
  const Result r =
      run("frame cornell-spot --width 16 --height 16 --enable rsm -p rsm.resolution=64 "
          "-p debug.show=rsm.flux:0 -o " +
          (dir_ / "f.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "f.png"));
}

TEST_F(CliRsm, BadLightsOrResolutionIsOneLineExitTwo) {
  // 1: no light of the one-light scene; all, -2: not an index or −1; 96: no resolution.
  for (const char* text :
       {"lights=1", "lights=all", "lights=-2", "resolution=96", "resolution=512"}) {
    const std::string bad(text);
    std::string key = "rsm.";
    key += bad.substr(0, bad.find('='));
    std::string cmd = "frame cornell-spot --width 16 --height 16 --enable rsm -p rsm.";
    cmd += bad;
    cmd += " -o ";
    cmd += (dir_ / "f.png").string();
    const Result r = run(cmd);
    expect_bad_input(r, key);
    EXPECT_FALSE(fs::exists(dir_ / "f.png")) << bad;
  }
}
#endif

}  // namespace
}  // namespace illum_cli_test
