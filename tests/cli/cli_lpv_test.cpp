// `--enable lpv` at the CLI: the frame is written and lists the lpv pass; a source that
// nothing declares, a grid size, a cascade count or an update period out of range is one line
// with exit code 2 and no output file.
#include <string>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliLpv : public CliTest {};

// `illum frame` exists only where the GPU layers are built (not in the asan tree).
#ifdef ILLUM_HAVE_GPU
TEST_F(CliLpv, FrameRunsTheVolume) {
  std::string command =
      "frame cornell --width 32 --height 32 --enable lpv -p lpv.grid=16 -p lpv.cascades=2 -o ";
  command += (dir_ / "lpv.png").string();
  const Result r = run(command);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "lpv.png"));
  EXPECT_NE(r.out.find("lpv.propagate"), std::string::npos) << r.out;
}

TEST_F(CliLpv, AnUndeclaredSourceIsOneLineExitTwo) {
  std::string command = "frame cornell --width 16 --height 16 --enable lpv -p lpv.source=nothing";
  const Result grid = run("frame cornell --width 16 --height 16 --enable lpv -p lpv.grid=24");
  expect_bad_input(grid, "-p lpv.grid=24: 16, 32 or 64");
  const Result cascades =
      run("frame cornell --width 16 --height 16 --enable lpv -p lpv.cascades=5");
  expect_bad_input(cascades, "parameter 'lpv.cascades' = 5 is outside [1, 4]");
  const Result period =
      run("frame cornell --width 16 --height 16 --enable lpv -p lpv.update_period=0");
  expect_bad_input(period, "parameter 'lpv.update_period' = 0 is outside [1, 8]");
  command += " -o " + (dir_ / "f.png").string();
  const Result r = run(command);
  expect_bad_input(r, "-p lpv.source=nothing: nothing in this frame declares 'nothing.position'");
  EXPECT_FALSE(fs::exists(dir_ / "f.png"));
}
#endif

}  // namespace
}  // namespace illum_cli_test
