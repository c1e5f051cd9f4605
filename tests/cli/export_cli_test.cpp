// `illum export SCENE --baked DIR -o OUT.glb`: a baked Cornell
// box exports to a .glb the project's own loader reads back, with OUT.lightmap.exr beside it;
// bad input — a folder baked for another scene, a missing or malformed folder, an output in
// a missing folder or not named .glb, an unknown --tone — is one line, exit 2, and nothing
// written (no .glb, no .exr, no temporary file). The round trip of the values themselves
// (uv1, RGBM texels, EXR) is tests/export/gltf_export_test.cpp.
#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class ExportCli : public CliTest {
 protected:
  fs::path bake(const std::string& scene, const std::string& name, const std::string& extra = "") {
    const fs::path folder = dir_ / name;
    const Result r = run("bake " + scene + " --resolution 32 --spp 1 --seed 1 " + extra + " -o " +
                         folder.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return folder;
  }
  Result do_export(const std::string& scene, const fs::path& folder, const fs::path& out,
                   const std::string& extra = "") {
    return run("export " + scene + " --baked " + folder.string() + " -o " + out.string() + " " +
               extra);
  }
  // Only the entries in `allowed` are in the test's folder: no output, no temporary file.
  void expect_only(const std::vector<std::string>& allowed) {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_NE(std::find(allowed.begin(), allowed.end(), name), allowed.end())
          << "left behind: " << entry.path();
    }
  }
};

TEST_F(ExportCli, CornellExportsAndLoadsBack) {
  const fs::path lm = bake("cornell", "lm");
  const fs::path out = dir_ / "cornell.glb";
  const Result r = do_export("cornell", lm, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_TRUE(fs::exists(dir_ / "cornell.lightmap.exr"));
  EXPECT_NE(r.out.find("MSFT_lightmap"), std::string::npos) << r.out;
  // The project's own loader reads it: same triangles, the camera, the area light rebuilt
  // from the emissive material.
  const Result info = run("info " + out.string() + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j.at("triangles"), 32);
  EXPECT_EQ(j.at("camera"), true);
  EXPECT_EQ(j.at("light_types").at("area"), 1);
  expect_only({"lm", "cornell.glb", "cornell.lightmap.exr", "stdout.txt", "stderr.txt"});
  // --tone lrp97 and an explicit range are accepted; a second export replaces the pair.
  const Result toned = do_export("cornell", lm, out, "--tone lrp97");
  EXPECT_EQ(toned.exit_code, 0) << toned.err;
  EXPECT_NE(toned.out.find("tone lrp97"), std::string::npos) << toned.out;
  expect_only({"lm", "cornell.glb", "cornell.lightmap.exr", "stdout.txt", "stderr.txt"});
}

// Every basis the baker writes exports (the dominant one stopped on an internal check).
TEST_F(ExportCli, EveryBakedBasisExports) {
  for (const std::string basis : {"plain", "rnm", "sh", "dominant"}) {
    const fs::path lm = bake("cornell", basis, "--basis " + basis);
    const Result r = do_export("cornell", lm, dir_ / (basis + ".glb"));
    EXPECT_EQ(r.exit_code, 0) << basis << ": " << r.err;
    EXPECT_TRUE(fs::exists(dir_ / (basis + ".glb"))) << basis;
  }
}

TEST_F(ExportCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path lm = bake("cornell", "lm");
  const fs::path out = dir_ / "out.glb";
  // Baked for another scene: same triangle count, moved 1 mm (the scene hash refuses it).
  const std::string moved = cornell_copy("moved", "{\"translate\": [0, 0.001, 0]}");
  expect_bad_input(do_export(moved, lm, out), "bake it again for this scene");
  // Another scene altogether (the triangle count refuses it).
  expect_bad_input(do_export("caustics", lm, out), "does not fit scene");
  // A missing folder, a folder without a manifest, a malformed manifest.
  expect_bad_input(do_export("cornell", dir_ / "nothing", out), "nothing");
  fs::create_directories(dir_ / "empty");
  expect_bad_input(do_export("cornell", dir_ / "empty", out), "empty");
  fs::create_directories(dir_ / "broken");
  write("broken/lightmap.json", "{\"format\": \"illum-lightmap\", ");
  expect_bad_input(do_export("cornell", dir_ / "broken", out), "broken");
  // The output: a missing folder, another extension, a folder in its place.
  expect_bad_input(do_export("cornell", lm, dir_ / "missing" / "out.glb"), "does not exist");
  expect_bad_input(do_export("cornell", lm, dir_ / "out.gltf"), "give a .glb file name");
  fs::create_directories(dir_ / "dir.glb");
  expect_bad_input(do_export("cornell", lm, dir_ / "dir.glb"), "is a folder");
  // Options.
  expect_bad_input(do_export("cornell", lm, out, "--tone aces"),
                   "--tone: aces not in {none,lrp97}");
  expect_bad_input(do_export("cornell", lm, out, "--rgbm-range -1"), "--rgbm-range");
  expect_bad_input(do_export("cornell", lm, out, "--rgbm-range nan"), "--rgbm-range");
  expect_only({"lm", "moved.illum.json", "empty", "broken", "dir.glb", "stdout.txt", "stderr.txt"});
  EXPECT_TRUE(fs::is_empty(dir_ / "dir.glb"));
}

}  // namespace
}  // namespace illum_cli_test
