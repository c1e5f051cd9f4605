// The SSAO add-on's parameters and the `ao` integrator's bias and falloff at the CLI: listed
// once from the declarations, and every bad value one line with exit code 2.
#include <string>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliSsao : public CliTest {};

// `illum frame` exists only where the GPU layers are built (not in the asan tree).
#ifdef ILLUM_HAVE_GPU
TEST_F(CliSsao, ListedWithEveryParameter) {
  const Result r = run("frame --list");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("  ssao (off by default): "), std::string::npos) << r.out;
  for (const char* key :
       {"radius", "bias", "intensity", "falloff", "samples", "blur", "output", "resolution"})
    EXPECT_NE(r.out.find(std::string("    ssao.") + key + "  "), std::string::npos) << key;
}

TEST_F(CliSsao, BadValuesAreOneLineExitTwo) {
  for (const std::string p :
       {"ssao.radius=-1", "ssao.bias=1", "ssao.bias=nan", "ssao.intensity=11", "ssao.falloff=-0.5",
        "ssao.samples=0", "ssao.samples=257", "ssao.blur=9", "ssao.output=normals",
        "ssao.radius=far", "ssao.resolution=quarter"}) {
    const Result r =
        run("frame cornell --enable ssao -p " + p + " -o " + (dir_ / "f.png").string());
    expect_bad_input(r, p.substr(0, p.find('=')));
    EXPECT_FALSE(fs::exists(dir_ / "f.png")) << p;
  }
}
#endif

TEST_F(CliSsao, AoIntegratorBadBiasAndFalloffAreOneLineExitTwo) {
  for (const std::string p : {"bias=1", "bias=-0.1", "falloff=-1", "falloff=near"}) {
    const Result r = run("render cornell -i ao --width 8 --height 8 --spp 1 -p " + p + " -o " +
                         (dir_ / "r.png").string());
    expect_bad_input(r, p.substr(0, p.find('=')));
    EXPECT_FALSE(fs::exists(dir_ / "r.png")) << p;
  }
}

}  // namespace
}  // namespace illum_cli_test
