// `illum bake --method radiosity`: writes a light-map folder the readers accept; a misspelt
// method, an absurd threshold or time, options of the other method and a scene without any
// light are one line on stderr, exit 2, nothing written (never a hang: a scene without light
// would otherwise have nothing to shoot and no power to measure convergence against).
#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class RadiosityCli : public CliTest {
 protected:
  void expect_nothing_written(const fs::path& out) {
    EXPECT_FALSE(fs::exists(out));
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path().filename().string().find(".lm"), std::string::npos)
          << "left behind: " << entry.path();
  }
};

TEST_F(RadiosityCli, BakesTheCornellBox) {
  const fs::path out = dir_ / "lm";
  const Result r =
      run("bake cornell --method radiosity --threshold 0.01 --resolution 24 -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("radiosity"), std::string::npos) << r.err;
  const nlohmann::json m = nlohmann::json::parse(slurp(out / "lightmap.json"));
  EXPECT_EQ(m.at("bake").at("method"), "radiosity");
  EXPECT_FLOAT_EQ(m.at("bake").at("threshold").get<float>(), 0.01f);
  EXPECT_TRUE(m.at("bake").at("converged").get<bool>());
  EXPECT_LE(m.at("bake").at("remaining_power").get<double>(),
            0.01 * m.at("bake").at("initial_power").get<double>());
  EXPECT_TRUE(fs::exists(out / "layer0.exr"));
}

TEST_F(RadiosityCli, BadMethodThresholdAndTimeAreRefused) {
  const fs::path out = dir_ / "lm";
  const std::string bake = "bake cornell --resolution 24 -o " + out.string() + " ";
  expect_bad_input(run(bake + "--method nonsense"), "--method: nonsense not in {path,radiosity}");
  expect_bad_input(run(bake + "--method radiosity --threshold -1"), "--threshold");
  expect_bad_input(run(bake + "--method radiosity --threshold nan"), "--threshold");
  expect_bad_input(run(bake + "--method radiosity --threshold 0"), "threshold");
  expect_bad_input(run(bake + "--method radiosity --threshold 1"), "threshold");
  expect_bad_input(run(bake + "--method radiosity --time -3"), "--time");
  expect_bad_input(run(bake + "--method radiosity --time inf"), "--time");
  expect_bad_input(run(bake + "--method radiosity --spp 4"), "--spp applies to --method path");
  expect_bad_input(run(bake + "--threshold 0.01"), "--threshold applies to --method radiosity");
  expect_bad_input(run(bake + "--method radiosity -p group_size=0"), "group_size");
  expect_bad_input(run(bake + "--method radiosity -p threshold=0.1"), "set it with --threshold");
  expect_nothing_written(out);
}

TEST_F(RadiosityCli, SceneWithoutLightIsRefused) {
  const fs::path scene = write("dark.obj",
                               "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
                               "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n"
                               "f 1 2 3 4\nf 8 7 6 5\nf 1 5 6 2\n");
  const fs::path out = dir_ / "lm";
  expect_bad_input(
      run("bake " + scene.string() + " --method radiosity --resolution 24 -o " + out.string()),
      "has no light");
  expect_nothing_written(out);
}

}  // namespace
}  // namespace illum_cli_test
