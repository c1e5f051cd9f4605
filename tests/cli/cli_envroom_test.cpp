// The built-in `envroom` scene at the CLI: it loads by name in the path tracer (rough copper,
// glass and mirror through NEE and BSDF sampling) and in the real-time frame.
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

class CliEnvroom : public CliTest {};

TEST_F(CliEnvroom, PathTracesByName) {
  const Result r =
      run("render envroom --spp 2 --width 16 --height 12 -o " + (dir_ / "r.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "r.png"));
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

// `illum frame` exists only where the GPU layers are built (not in the asan tree).
#ifdef ILLUM_HAVE_GPU
TEST_F(CliEnvroom, RendersAFrameByName) {
  const Result r = run("frame envroom --width 16 --height 12 -o " + (dir_ / "f.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "f.png"));
}
#endif

}  // namespace
}  // namespace illum_cli_test
