// A damaged bake manifest read by the CLI: exit 2, one stderr line naming the manifest's
// field, no output. The field-by-field table is ManifestFieldsTest (tests/baked); this runs a
// few of its cases through `illum frame --baked` for each folder kind.
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"

using namespace illum_cli_test;

namespace {

#ifdef ILLUM_HAVE_GPU  // `illum frame` exists only in builds with the real-time renderer
class BakedManifestCli : public CliTest {
 protected:
  // Each bad value at `key` of `folder`'s `manifest` (null: the key removed) makes `frame`
  // refuse with one line naming the key; the good manifest is put back and works.
  void check(const std::string& scene, const fs::path& folder, const std::string& manifest,
             const std::string& key, const std::vector<nlohmann::json>& bad) {
    const fs::path path = folder / manifest;
    const std::string good = slurp(path);
    const std::string frame = "frame " + scene + " --baked " + folder.string() +
                              " --width 16 --height 16 -o " + (dir_ / "f.png").string();
    for (const nlohmann::json& value : bad) {
      SCOPED_TRACE(manifest + ": " + key + " = " + value.dump());
      nlohmann::json j = nlohmann::json::parse(good);
      if (value.is_null())
        j.erase(key);
      else
        j[key] = value;
      std::ofstream(path) << j.dump();
      expect_bad_input(run(frame), "'" + key + "'");
      EXPECT_FALSE(fs::exists(dir_ / "f.png"));
    }
    std::ofstream(path) << good;
    const Result ok = run(frame);
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    fs::remove(dir_ / "f.png");
  }
};

TEST_F(BakedManifestCli, DamagedFieldsAreOneLineAndExitTwo) {
  const fs::path lm = dir_ / "lm", prt = dir_ / "prt", probes = dir_ / "probes";
  ASSERT_EQ(run("bake cornell --resolution 16 --spp 1 -o " + lm.string()).exit_code, 0);
  ASSERT_EQ(
      run("bake cornell --kind prt --resolution 16 --spp 1 --bands 2 -o " + prt.string()).exit_code,
      0);
  // A scene with a dynamic object, which the probes light.
  const std::string dynamic =
      std::string(ILLUM_DATA_DIR) + "/scenes/cornell-dynamic/cornell-dynamic.illum.json";
  ASSERT_EQ(run("bake " + dynamic + " --kind probes --spp 1 -o " + probes.string()).exit_code, 0);
  check("cornell", lm, "lightmap.json", "texel_size", {"big", -1, 0, 1e12, nullptr});
  check("cornell", lm, "lightmap.json", "scene", {7, nullptr});
  check("cornell", prt, "prt.json", "coefficients", {0, 1e12, 5, "4", nullptr});
  check(dynamic, probes, "probes.json", "valid", {-1, "NaN", 1e12, nullptr});
}
#endif

}  // namespace
