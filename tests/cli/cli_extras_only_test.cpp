// `illum bake --basis none --extras ...`: the extra maps without the light-map layers, in the
// same folder format; the same maps as a full bake with the same seed; readers that need the
// layers refuse such a folder in one line.
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliExtrasOnly : public CliTest {
 protected:
  static constexpr const char* kCommon =
      " --resolution 32 --extras ao,bent_normal --extras-rays 16 --seed 7";
};

TEST_F(CliExtrasOnly, WritesOnlyTheExtraMapsAndTheyMatchAFullBake) {
  const fs::path full = dir_ / "full", only = dir_ / "only";
  const Result a = run("bake cornell -o " + full.string() + " --spp 2" + kCommon);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const Result b = run("bake cornell -o " + only.string() + " --basis none" + kCommon);
  ASSERT_EQ(b.exit_code, 0) << b.err;

  const nlohmann::json m = nlohmann::json::parse(slurp(only / "lightmap.json"));
  EXPECT_EQ(m.at("basis"), "none");
  EXPECT_EQ(m.at("content"), "none");
  EXPECT_TRUE(m.at("layers").empty());
  EXPECT_EQ(m.at("extras").size(), 2u);
  EXPECT_EQ(m.at("bake").at("method"), "none");
  std::set<std::string> files;
  for (const auto& entry : fs::directory_iterator(only))
    files.insert(entry.path().filename().string());
  EXPECT_EQ(files, (std::set<std::string>{"lightmap.json", "atlas.bin", "preview.png", "ao.exr",
                                          "bent_normal.exr"}));
  // The extra maps depend on the atlas, the seed and the rays alone: byte for byte the full
  // bake's.
  for (const char* map : {"ao.exr", "bent_normal.exr", "atlas.bin"})
    EXPECT_TRUE(slurp(only / map) == slurp(full / map)) << map;

  // Baking over it again replaces it, as any bake folder.
  EXPECT_EQ(run("bake cornell -o " + only.string() + " --basis none" + kCommon).exit_code, 0);
}

TEST_F(CliExtrasOnly, ReadersThatNeedTheLayersRefuseInOneLine) {
  const fs::path only = dir_ / "only";
  ASSERT_EQ(run("bake cornell -o " + only.string() + " --basis none" + kCommon).exit_code, 0);
  const fs::path glb = dir_ / "e.glb";
  expect_bad_input(run("export cornell --baked " + only.string() + " -o " + glb.string()),
                   "holds only extra maps (ao, bent_normal");
  EXPECT_FALSE(fs::exists(glb));
#ifdef ILLUM_HAVE_GPU
  const fs::path png = dir_ / "f.png";
  expect_bad_input(
      run("frame cornell --baked " + only.string() + " --width 16 --height 16 -o " + png.string()),
      "no light-map layers to show");
  EXPECT_FALSE(fs::exists(png));
#endif
}

TEST_F(CliExtrasOnly, OptionsOfTheLayersAreRefused) {
  const std::string bake = "bake cornell --resolution 32 --basis none -o " + (dir_ / "x").string();
  expect_bad_input(run(bake), "--basis none bakes only the extra maps");
  expect_bad_input(run(bake + " --extras ao --spp 4"), "--spp does not apply to --basis none");
  expect_bad_input(run(bake + " --extras ao --method radiosity"), "--method does not apply");
  expect_bad_input(run(bake + " --extras ao --content indirect"), "--content does not apply");
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

}  // namespace
}  // namespace illum_cli_test
