// Hostile scene files through the real `illum` binary: each must end with exit code 2, exactly
// one stderr line naming the file, and — for `render -o x.png` — no image. The inputs are
// generated here (a million-level nesting is 2 MB; nothing big is committed).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../scene/gltf_asset.h"
#include "cli_fixture.h"

using namespace illum_cli_test;
using nlohmann::json;

namespace {

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

class CliSceneErrors : public CliTest {
 protected:
  // `info` and `render` on the file: exit 2, one line naming it, no image written.
  void expect_refused(const fs::path& scene, const std::string& also = "") {
    const std::string name = scene.filename().string();
    const Result info = run("info " + scene.string());
    expect_bad_input(info, name);
    if (!also.empty()) {
      EXPECT_NE(info.err.find(also), std::string::npos) << info.err;
    }
    const fs::path image = dir_ / "x.png";
    fs::remove(image);  // callers loop over files: each run must show its own result
    const Result render =
        run("render " + scene.string() + " --integrator ao --spp 1 -o " + image.string());
    expect_bad_input(render, name);
    EXPECT_FALSE(fs::exists(image));
  }
  fs::path write_asset(const std::string& name, const illum::test::Asset& a) {
    return write(name, illum::test::gltf_text(a));
  }
};

TEST_F(CliSceneErrors, DeepNestingInGltfAndSceneFiles) {
  const std::string deep = std::string(1000000, '[') + std::string(1000000, ']');
  std::string gltf = illum::test::gltf_text(illum::test::make_asset());
  gltf.insert(gltf.rfind('}'), ", \"extras\": " + deep);
  expect_refused(write("deep.gltf", gltf), "nested deeper than 128 levels");
  expect_refused(write("deep.illum.json", "{\"description\": " + deep + "}"),
                 "nested deeper than 128 levels");
}

TEST_F(CliSceneErrors, NumberBeyondADouble) {
  std::string gltf = illum::test::gltf_text(illum::test::make_asset());
  gltf.insert(gltf.rfind('}'), ", \"extras\": 1e400");
  expect_refused(write("big.gltf", gltf), "1e400");
  write("tri.obj", kTriangleObj);
  expect_refused(write("big.illum.json", R"({"meshes": [{"file": "tri.obj"}], "name": 1e400})"),
                 "1e400");
  // The same number as an option value names the option.
  const fs::path image = dir_ / "x.png";
  const Result r =
      run("render cornell --integrator ao --spp 1 -p radius=1e400 -o " + image.string());
  expect_bad_input(r, "--param 'radius=1e400'");
  EXPECT_FALSE(fs::exists(image));
}

TEST_F(CliSceneErrors, DeepParamValue) {
  // 60,000 levels: 120 kB, under the kernel's 128 kB limit for one argument. Params copies
  // the value recursively, so it must be refused before parsing.
  const std::string deep = std::string(60000, '[') + std::string(60000, ']');
  const fs::path image = dir_ / "x.png";
  const Result r =
      run("render cornell --integrator ao --spp 1 -p 'radius=" + deep + "' -o " + image.string());
  expect_bad_input(r, "nested deeper than 128 levels");
  EXPECT_FALSE(fs::exists(image));
}

TEST_F(CliSceneErrors, CountsBeyondTheBytes) {
  illum::test::Asset zeros = illum::test::make_asset();
  zeros.json["accessors"][0].erase("bufferView");
  zeros.json["accessors"][0]["count"] = 2000000000;
  zeros.json["meshes"][0]["primitives"][0].erase("indices");
  zeros.json["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
  expect_refused(write_asset("zeros.gltf", zeros), "declares far more data than it holds");
  illum::test::Asset stride = illum::test::make_asset();
  stride.json["bufferViews"][0]["byteOffset"] = -4;
  expect_refused(write_asset("offset.gltf", stride), "byteOffset = -4");
}

TEST_F(CliSceneErrors, GltfValuesAndReferences) {
  const std::vector<std::pair<const char*, void (*)(json&)>> cases = {
      {"emission.gltf",
       [](json& j) {
         j["materials"][0]["emissiveFactor"] = {-1, 0, 0};
       }},
      {"extension.gltf", [](json& j) { j["extensionsRequired"] = {"EXT_meshopt_compression"}; }},
      {"scene.gltf", [](json& j) { j["scene"] = 7; }},
      {"light.gltf",
       [](json& j) { j["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = 1e39; }},
      {"cycle.gltf", [](json& j) { j["nodes"][1]["children"] = {0}; }},
  };
  for (const auto& [name, mutate] : cases) {
    SCOPED_TRACE(name);
    illum::test::Asset a = illum::test::make_asset();
    mutate(a.json);
    expect_refused(write_asset(name, a));
  }
}

// The asset's points primitive is skipped with a warning; a later fatal error must still be
// the only line on stderr. A good run prints its warning.
TEST_F(CliSceneErrors, OneLineEvenAfterWarnings) {
  illum::test::Asset a = illum::test::make_asset();
  const Result ok = run("info " + write_asset("good.gltf", a).string());
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.err.find("mode 0"), std::string::npos) << ok.err;
  a.json["nodes"][1]["scale"] = {0, 1, 1};
  expect_refused(write_asset("warned.gltf", a), "singular transform");
}

// The load succeeds with a warning and a later check refuses the run: still one line (the
// CLI holds the log until the command has checked its input), while a run that goes on
// prints the warning.
TEST_F(CliSceneErrors, OneLineWhenARefusalFollowsASuccessfulLoad) {
  const std::string warned = write_asset("warned.gltf", illum::test::make_asset()).string();
  const std::string out = (dir_ / "x.png").string();
  const std::string tiny = " --width 4 --height 4 --spp 1 -o " + out;
  const Result bad_param = run("render " + warned + " -i path -p no_such_key=1" + tiny);
  expect_bad_input(bad_param, "no_such_key");
  EXPECT_EQ(bad_param.err.find("mode 0"), std::string::npos) << bad_param.err;
#ifdef ILLUM_HAVE_GPU
  // The real-time renderer refuses a light index the scene does not have (after the load).
  const Result bad_light =
      run("frame " + warned + " -p single_light=99 --width 4 --height 4 -o " + out);
  expect_bad_input(bad_light, "single_light");
  EXPECT_EQ(bad_light.err.find("mode 0"), std::string::npos) << bad_light.err;
#endif
  EXPECT_FALSE(fs::exists(out));
  const Result ok = run("render " + warned + " -i ao" + tiny);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.err.find("mode 0"), std::string::npos) << ok.err;
}

TEST_F(CliSceneErrors, MtlValuesUnderTheSharedRules) {
  write("neg.mtl", "newmtl wood\nKd -0.5 0.4 0.3\n");
  expect_refused(write("neg.obj", std::string("mtllib neg.mtl\nusemtl wood\n") + kTriangleObj),
                 "albedo");
}

TEST_F(CliSceneErrors, GlbContainer) {
  // A GLB whose JSON chunk claims a gigabyte.
  std::string glb = "glTF";
  auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  u32(2);
  u32(24);
  u32(1u << 30);
  u32(0x4E4F534Au);
  glb += "{}  ";
  expect_refused(write("chunk.glb", glb), "JSON chunk");
}

}  // namespace
