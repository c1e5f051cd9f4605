// `--enable vpl` at the CLI: the frame is written and lists the vpl passes; a count that is
// not one of the four, a source nothing declares and the deferred pipeline are one line
// with exit code 2 and no output file.
#include <string>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliVpl : public CliTest {};

// `illum frame` exists only where the GPU layers are built (not in the asan tree).
#ifdef ILLUM_HAVE_GPU
TEST_F(CliVpl, FrameRunsTheVirtualPointLights) {
  std::string command =
      "frame cornell-spot --width 32 --height 32 --enable vpl -p vpl.count=64 -p vpl.clamp=0.1 -o ";
  command += (dir_ / "vpl.png").string();
  const Result r = run(command);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "vpl.png"));
  EXPECT_NE(r.out.find("vpl.build"), std::string::npos) << r.out;
}

TEST_F(CliVpl, BadCountSourceOrPipelineIsOneLineExitTwo) {
  const std::string out = " -o " + (dir_ / "f.png").string();
  std::string base = "frame cornell-spot --width 16 --height 16 --enable vpl ";
  expect_bad_input(run(base + "-p vpl.count=100" + out),
                   "-p vpl.count=100: one of 64, 256, 1024, 4096");
  expect_bad_input(run(base + "-p vpl.source=nothing" + out),
                   "-p vpl.source=nothing: nothing in this frame declares 'nothing.position'");
  expect_bad_input(run(base + "-t deferred" + out),
                   "vpl: the deferred pipeline applies screen-space lighting inputs' occlusion "
                   "only, not an indirect term; use -t forward or visibility");
  EXPECT_FALSE(fs::exists(dir_ / "f.png"));
}
#endif

}  // namespace
}  // namespace illum_cli_test
