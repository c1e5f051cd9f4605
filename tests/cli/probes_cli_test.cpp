// `illum bake --kind probes`: a bake that works, dynamic objects left out
// of the bake and its scene hash, and bad input — spacings ≤ 0, NaN or too fine for memory,
// --spp 0, options of other kinds, an unlit scene, a malformed "dynamic" — each one line,
// exit 2, and no folder written.
#include <fstream>

#include "cli_fixture.h"
#include "illum/core/image.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;
using illum_cli_test::slurp;

class ProbesCli : public CliTest {
 protected:
  Result bake(const std::string& scene, const fs::path& folder, const std::string& extra = "") {
    return run("bake " + scene + " --kind probes --spp 4 --seed 1 " + extra + " -o " +
               folder.string());
  }
  // The manifest's value of "key" as text (the JSON is written with 2-space indents).
  static std::string manifest_value(const fs::path& folder, const std::string& key) {
    const std::string m = slurp(folder / "probes.json");
    const size_t at = m.find("\"" + key + "\": ");
    if (at == std::string::npos) return "";
    const size_t start = at + key.size() + 4;
    return m.substr(start, m.find_first_of(",\n", start) - start);
  }
  std::string cornell_obj() const {
    return std::string(ILLUM_DATA_DIR) + "/scenes/cornell/cornell_box.obj";
  }
};

TEST_F(ProbesCli, BakesAFolderWithManifestAndData) {
  const fs::path folder = dir_ / "probes";
  const Result r = bake("cornell", folder, "--spacing 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(folder / "probes.bin"));
  EXPECT_EQ(manifest_value(folder, "format"), "\"illum-probes\"");
  EXPECT_EQ(manifest_value(folder, "probes"), "180");  // 0.556 × 0.549 × 0.559 m / 0.1 → 6 × 5 × 6
  EXPECT_EQ(manifest_value(folder, "scene_hash").size(), 18u);
  EXPECT_NE(r.err.find("probes: 6x5x6 grid"), std::string::npos) << r.err;
  // Baking again replaces the folder.
  EXPECT_EQ(bake("cornell", folder, "--spacing 0.2").exit_code, 0);
  EXPECT_EQ(manifest_value(folder, "probes"), "27");
}

TEST_F(ProbesCli, LeavesDynamicObjectsOutOfTheBakeAndItsHash) {
  const fs::path plain = dir_ / "plain", with = dir_ / "with";
  ASSERT_EQ(bake("cornell", plain, "--spacing 0.1").exit_code, 0);
  // The box again, far off to the side and marked dynamic: the bake's bounds, grid and scene
  // hash are those of the box alone.
  const std::string scene =
      write("dyn.illum.json",
            "{\"meshes\": [{\"file\": \"" + cornell_obj() + "\", \"scale\": 0.001}, {\"file\": \"" +
                cornell_obj() +
                "\", \"scale\": 0.001, \"transform\": {\"translate\": [5, 0, 0]}, "
                "\"dynamic\": true}]}")
          .string();
  const Result r = bake(scene, with, "--spacing 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(manifest_value(with, "scene_hash"), manifest_value(plain, "scene_hash"));
  EXPECT_EQ(manifest_value(with, "probes"), "180");
  const std::string bad = write("bad.illum.json", "{\"meshes\": [{\"file\": \"" + cornell_obj() +
                                                      "\", \"dynamic\": \"yes\"}]}")
                              .string();
  expect_bad_input(bake(bad, dir_ / "bad"), "dynamic");
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(ProbesCli, RefusesBadInputWithOneLineAndWritesNothing) {
  const fs::path folder = dir_ / "probes";
  expect_bad_input(bake("cornell", folder, "--spacing 0"), "--spacing");
  expect_bad_input(bake("cornell", folder, "--spacing -0.5"), "--spacing");
  expect_bad_input(bake("cornell", folder, "--spacing nan"), "--spacing");
  // 0.56 m at 0.1 mm: 5590³ ≈ 1.7e11 probes.
  const Result huge = bake("cornell", folder, "--spacing 0.0001");
  expect_bad_input(huge, "--spacing");
  EXPECT_NE(huge.err.find("probes"), std::string::npos) << huge.err;
  EXPECT_NE(huge.err.find("bytes"), std::string::npos) << huge.err;
  expect_bad_input(bake("cornell", folder, "--spp 0"), "--spp");
  expect_bad_input(bake("cornell", folder, "--time 5"), "--time");
  expect_bad_input(bake("cornell", folder, "--basis sh"), "--basis");
  expect_bad_input(bake("cornell", folder, "-p backface_threshold=2"), "backface_threshold");
  expect_bad_input(bake("cornell", folder, "-p spacing=0.1"), "--spacing");
  expect_bad_input(run("bake cornell --spacing 0.1 -o " + folder.string()), "--kind probes");
  // An unlit scene: every probe would be black.
  const std::string obj = write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").string();
  expect_bad_input(bake(obj, folder), "has no light");
  EXPECT_FALSE(fs::exists(folder));
  fs::create_directories(dir_ / "unrelated");
  std::ofstream(dir_ / "unrelated" / "keep.txt") << "mine";
  expect_bad_input(bake("cornell", dir_ / "unrelated"), "not a probe folder");
  EXPECT_TRUE(fs::exists(dir_ / "unrelated" / "keep.txt"));
}

}  // namespace

#ifdef ILLUM_HAVE_GPU  // `illum frame` exists only in builds with the real-time renderer
// `illum frame --baked DIR` with a probe folder: the dynamic instances take the probes'
// ambient cubes (the frame differs from the one without them, and only on the dynamic
// object's pixels, static surfaces unchanged); probes for a scene that marks nothing dynamic,
// and probes baked for another scene, are refused with one line.
TEST_F(ProbesCli, FrameShowsProbesOnDynamicObjectsOnly) {
  // A small copy of the box inside the box, marked dynamic; the built-in scene's camera.
  const std::string camera =
      "\"camera\": {\"position\": [0.278, 0.273, -0.8], \"look_at\": [0.278, 0.273, 0], "
      "\"up\": [0, 1, 0], \"fov_y_deg\": 39.3077}, ";
  const std::string scene =
      write("inside.illum.json",
            "{" + camera + "\"meshes\": [{\"file\": \"" + cornell_obj() +
                "\", \"scale\": 0.001}, {\"file\": \"" + cornell_obj() +
                "\", \"scale\": 0.0002, \"transform\": {\"translate\": [0.2, 0.1, 0.2]}, "
                "\"dynamic\": true}]}")
          .string();
  const fs::path probes = dir_ / "probes";
  ASSERT_EQ(bake(scene, probes, "--spacing 0.1").exit_code, 0);
  const std::string frame = " --width 48 --height 48 --frames 1 --warmup 0 -o ";
  const Result with =
      run("frame " + scene + " --baked " + probes.string() + frame + (dir_ / "with.exr").string());
  ASSERT_EQ(with.exit_code, 0) << with.err;
  const Result without = run("frame " + scene + frame + (dir_ / "without.exr").string());
  ASSERT_EQ(without.exit_code, 0) << without.err;
  const illum::Image a = illum::read_image((dir_ / "with.exr").string(), false);
  const illum::Image b = illum::read_image((dir_ / "without.exr").string(), false);
  // The same scene drawn without the dynamic object tells which pixels are static.
  const std::string static_scene =
      write("static.illum.json",
            "{" + camera + "\"meshes\": [{\"file\": \"" + cornell_obj() + "\", \"scale\": 0.001}]}")
          .string();
  ASSERT_EQ(run("frame " + static_scene + frame + (dir_ / "static.exr").string()).exit_code, 0);
  const illum::Image s = illum::read_image((dir_ / "static.exr").string(), false);
  int changed_dynamic = 0, changed_static = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const bool dynamic_pixel = glm::any(glm::notEqual(b.rgb(x, y), s.rgb(x, y)));
      const bool changed = glm::any(glm::notEqual(a.rgb(x, y), b.rgb(x, y)));
      (dynamic_pixel ? changed_dynamic : changed_static) += changed;
    }
  EXPECT_GT(changed_dynamic, 10) << "the probes did not reach the dynamic object";
  EXPECT_EQ(changed_static, 0) << "the probes changed static surfaces";

  expect_bad_input(run("frame " + static_scene + " --baked " + probes.string() + frame +
                       (dir_ / "x.exr").string()),
                   "dynamic");
  expect_bad_input(
      run("frame caustics --baked " + probes.string() + frame + (dir_ / "y.exr").string()),
      probes.string());
  EXPECT_FALSE(fs::exists(dir_ / "x.exr"));
  EXPECT_FALSE(fs::exists(dir_ / "y.exr"));
}
#endif
