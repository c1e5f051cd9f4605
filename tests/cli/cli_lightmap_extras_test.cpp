// `illum bake --extras`: the extra maps land in the folder with their manifest entries; an
// unknown or repeated map name, or an absurd parameter, is one line, exit 2, nothing written.
#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliLightmapExtras : public CliTest {};

TEST_F(CliLightmapExtras, WritesTheAskedForMaps) {
  const fs::path out = dir_ / "lm";
  const Result r = run("bake cornell -o " + out.string() +
                       " --resolution 32 --spp 1 --extras ao,obscurance --extras-rays 8 "
                       "--ao-distance 0.2 --obscurance-dmax 0.25 --seed 5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json m = nlohmann::json::parse(slurp(out / "lightmap.json"));
  const nlohmann::json& e = m.at("extras");
  EXPECT_EQ(e.size(), 3u);  // obscurance writes both the plain and the colour map
  EXPECT_FLOAT_EQ(e.at("ao").at("distance").get<float>(), 0.2f);
  EXPECT_FLOAT_EQ(e.at("obscurance").at("d_max").get<float>(), 0.25f);
  EXPECT_EQ(e.at("obscurance_color").at("rays"), 8);
  EXPECT_EQ(e.at("ao").at("seed"), 5);
  EXPECT_EQ(e.count("bent_normal"), 0u);
  for (const char* f : {"ao.exr", "obscurance.exr", "obscurance_color.exr", "layer0.exr"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_FALSE(fs::exists(out / "bent_normal.exr"));
}

TEST_F(CliLightmapExtras, BadExtrasAreRefusedBeforeAnyWork) {
  const fs::path out = dir_ / "lm";
  const std::string bake = "bake cornell -o " + out.string() + " --resolution 32 --spp 1 ";
  expect_bad_input(run(bake + "--extras ao,fog"), "unknown extra map 'fog'");
  expect_bad_input(run(bake + "--extras ao,ao"), "'ao' is listed twice");
  expect_bad_input(run(bake + "--extras ao --extras-rays 0"), "--extras-rays");
  expect_bad_input(run(bake + "--extras obscurance --obscurance-dmax 0"), "--obscurance-dmax");
  expect_bad_input(run(bake + "--extras ao --ao-distance -1"), "--ao-distance");
  EXPECT_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".lm"), std::string::npos)
        << "left behind: " << entry.path();
}

}  // namespace
}  // namespace illum_cli_test
