// The `illum` program on scenes whose side files are missing, truncated or hostile
// (textures, .mtl files, environment maps, glTF images, OBJ text) and on bad light-map
// folders: exit code 2, exactly one stderr line naming the file, no output file left; and
// --allow-missing-textures on every subcommand that loads a scene. Commands that once hung
// (a truncated Radiance HDR) run under `timeout`, so a regression fails instead of stalling.
#include <algorithm>
#include <initializer_list>
#include <limits>
#include <sstream>

#include "cli_fixture.h"
#include "illum/core/image.h"

using namespace illum_cli_test;

namespace {

const char* kQuadObj =
    "mtllib m.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
    "usemtl wood\nf 1/1 2/2 3/3\n";

class CliFileErrors : public CliTest {
 protected:
  // run() under `timeout`: a hang ends with exit code 124 after `seconds`.
  Result run_within(int seconds, const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = "timeout " + std::to_string(seconds) + " " +
                            std::string(ILLUM_BINARY_DIR) + "/bin/illum " + args + " >" +
                            out.string() + " 2>" + err.string() + " </dev/null";
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  // Files in the test folder other than the inputs and the captured streams.
  int outputs_left(std::initializer_list<std::string> inputs) const {
    int n = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      if (name == "stdout.txt" || name == "stderr.txt" || e.is_directory()) continue;
      if (std::find(inputs.begin(), inputs.end(), name) == inputs.end()) ++n;
    }
    return n;
  }
  // A Radiance file cut inside its run-length data (stb looped forever on it).
  void write_truncated_hdr(const std::string& name) {
    illum::write_image((dir_ / "whole.hdr").string(), illum::Image(64, 4, 3, 0.5f));
    const std::string bytes = slurp(dir_ / "whole.hdr");
    fs::remove(dir_ / "whole.hdr");
    write(name, bytes.substr(0, bytes.size() - 40));
  }
};

TEST_F(CliFileErrors, TruncatedHdrEnvironmentIsOneLineNotAHang) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write_truncated_hdr("sky.hdr");
  const auto scene = write(
      "s.illum.json", R"({"meshes": [{"file": "tri.obj"}], "environment": {"file": "sky.hdr"}})");
  const fs::path out = dir_ / "out.png";
  expect_bad_input(run_within(60, "render " + scene.string() + " --width 8 --height 8 --spp 1 -o " +
                                      out.string()),
                   "sky.hdr");
  EXPECT_EQ(outputs_left({"tri.obj", "sky.hdr", "s.illum.json"}), 0);
  expect_bad_input(run_within(60, "info " + scene.string()), "truncated");
}

TEST_F(CliFileErrors, TruncatedHdrTextureFromMtlIsOneLineNotAHang) {
  write("m.mtl", "newmtl wood\nmap_Kd wood.hdr\n");
  write_truncated_hdr("wood.hdr");
  const auto obj = write("t.obj", kQuadObj);
  const auto r = run_within(60, "info " + obj.string());
  expect_bad_input(r, "wood.hdr");
  EXPECT_NE(r.err.find("'wood'"), std::string::npos) << r.err;
}

TEST_F(CliFileErrors, MissingTextureIsAnErrorUnlessAllowed) {
  write("m.mtl", "newmtl wood\nmap_Kd gone.png\n");
  const auto obj = write("t.obj", kQuadObj);
  const fs::path out = dir_ / "out.png";
  const std::string render = "render " + obj.string() + " --width 8 --height 8 --spp 1 -o ";
  const auto r = run(render + out.string());
  expect_bad_input(r, "gone.png");
  EXPECT_NE(r.err.find("'wood'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(outputs_left({"m.mtl", "t.obj"}), 0);
  // Allowed: the render goes on with exactly one warning about it (the scene also has no
  // lights, which is a warning of its own).
  const auto allowed = run(render + out.string() + " --allow-missing-textures");
  ASSERT_EQ(allowed.exit_code, 0) << allowed.err;
  EXPECT_TRUE(fs::exists(out));
  int about_it = 0;
  std::istringstream lines(allowed.err);
  for (std::string line; std::getline(lines, line);)
    about_it +=
        line.find("[warning]") != std::string::npos && line.find("gone.png") != std::string::npos;
  EXPECT_EQ(about_it, 1) << allowed.err;
}

TEST_F(CliFileErrors, MissingMtlIsAMissingFile) {
  const auto obj = write("t.obj", kQuadObj);
  expect_bad_input(run("info " + obj.string()), "m.mtl");
  EXPECT_EQ(run("info " + obj.string() + " --allow-missing-textures").exit_code, 0);
}

TEST_F(CliFileErrors, ImageBombsAreRefusedNamingTheFile) {
  // An 8-bit grey PNG declaring w × h pixels over 100 bytes of data.
  auto png = [](uint32_t w, uint32_t h) {
    auto be = [](uint32_t v) {
      return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                         static_cast<char>(v >> 8), static_cast<char>(v)};
    };
    return std::string("\x89PNG\r\n\x1a\n") + be(13) + "IHDR" + be(w) + be(h) +
           std::string("\x08\0\0\0\0", 5) + be(0) + be(100) + "IDAT" + std::string(100, 'x') +
           be(0) + be(0) + "IEND" + be(0);
  };
  write("m.mtl", "newmtl wood\nmap_Kd bomb.png\n");
  const auto obj = write("t.obj", kQuadObj);
  write("bomb.png", png(60000, 60000));
  expect_bad_input(run_within(60, "info " + obj.string()), "bomb.png");
  write("bomb.png", png(16000, 16000));
  const auto r = run_within(60, "info " + obj.string());
  expect_bad_input(r, "bomb.png");
  EXPECT_NE(r.err.find("deflate"), std::string::npos) << r.err;
}

TEST_F(CliFileErrors, NonFiniteEnvironmentTexelIsNamed) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  illum::Image sky(4, 2, 3, 1.0f);
  sky.pixel(1, 0)[1] = std::numeric_limits<float>::infinity();
  illum::ImageWriteOptions exact;
  exact.exr_half = false;
  illum::write_image((dir_ / "sky.exr").string(), sky, exact);
  const auto scene = write(
      "s.illum.json", R"({"meshes": [{"file": "tri.obj"}], "environment": {"file": "sky.exr"}})");
  const auto r = run("info " + scene.string());
  expect_bad_input(r, "sky.exr");
  EXPECT_NE(r.err.find("texel (1, 0) channel 1 is infinite"), std::string::npos) << r.err;
}

TEST_F(CliFileErrors, HostileObjTextNamesTheLine) {
  std::string polygon;
  for (int i = 0; i < 2000; ++i) polygon += fmt::format("v {} {} 0\n", i % 7, i % 5);
  polygon += "f";
  for (int i = 1; i <= 2000; ++i) polygon += fmt::format(" {}", i);
  const struct {
    const char* name;
    std::string text;
    const char* expected;
  } cases[] = {{"face.obj", polygon + "\n", "line 2001"},
               {"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "line 4"},
               {"overflow.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", "line 2"},
               {"binary.obj", std::string("v 0 0 0\n\0\x01\x02", 11), "NUL byte"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto path = write(c.name, c.text);
    const auto r = run_within(60, "info " + path.string());
    expect_bad_input(r, c.name);
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  }
}

TEST_F(CliFileErrors, EveryCommandThatLoadsASceneTakesAllowMissingTextures) {
  write("m.mtl", "newmtl wood\nmap_Kd gone.png\n");
  const auto obj = write("t.obj", kQuadObj).string();
  const fs::path lm = dir_ / "lm";
  expect_bad_input(run("bake " + obj + " --resolution 16 --spp 1 -o " + lm.string()), "gone.png");
  EXPECT_FALSE(fs::exists(lm));
  const auto baked =
      run("bake " + obj + " --resolution 16 --spp 1 --allow-missing-textures -o " + lm.string());
  EXPECT_EQ(baked.exit_code, 0) << baked.err;
  EXPECT_EQ(run("info " + obj + " --allow-missing-textures").exit_code, 0);
#ifdef ILLUM_HAVE_GPU
  // frame and view take the flag too: what fails next is the (missing) light-map folder, not
  // an unknown option.
  const fs::path frame = dir_ / "frame.png";
  for (const std::string command : {"frame", "view"}) {
    SCOPED_TRACE(command);
    const auto r =
        run(command + " cornell --allow-missing-textures --baked " + (dir_ / "none").string() +
            (command == "frame" ? " -o " + frame.string() : ""));
    expect_bad_input(r, "none");
    EXPECT_EQ(r.err.find("allow-missing-textures"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(frame));
#endif
}

#ifdef ILLUM_HAVE_GPU
// Extends CliTest.FrameRefusesBadLightmapFolders: wrong manifest types, paths outside the
// folder, a layer with a NaN texel or the wrong size.
TEST_F(CliFileErrors, FrameRefusesBadLightmapFolders) {
  const fs::path folder = dir_ / "lm";
  ASSERT_EQ(run("bake cornell --resolution 32 --spp 1 -o " + folder.string()).exit_code, 0);
  const std::string manifest = slurp(folder / "lightmap.json");
  const fs::path frame = dir_ / "frame.png";
  const std::string cmd = "frame cornell --baked " + folder.string() + " -o " + frame.string();
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string m = manifest;
    const size_t at = m.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    write("lm/lightmap.json", m.replace(at, from.size(), to));
  };
  replace("\"version\": 1", "\"version\": \"1\"");
  expect_bad_input(run(cmd), "'version' must be an integer");
  replace("\"atlas\": \"atlas.bin\"", "\"atlas\": \"../lm/atlas.bin\"");
  expect_bad_input(run(cmd), "must be a file in the folder");
  replace("\"content\": \"all\"", "\"content\": 3");
  expect_bad_input(run(cmd), "lightmap.json");
  write("lm/lightmap.json", manifest);
  illum::Image layer(32, 32, 3, 0.5f);
  layer.pixel(4, 7)[0] = std::numeric_limits<float>::quiet_NaN();
  illum::write_image((folder / "layer0.exr").string(), layer);
  expect_bad_input(run(cmd), "texel (4, 7) channel 0 is NaN");
  illum::write_image((folder / "layer0.exr").string(), illum::Image(16, 32, 3, 0.5f));
  expect_bad_input(run(cmd), "layer0.exr");
  std::string atlas = slurp(folder / "atlas.bin");
  write("lm/atlas.bin", atlas.substr(0, atlas.size() / 2));
  expect_bad_input(run(cmd), "atlas.bin");
  EXPECT_FALSE(fs::exists(frame));
}
#endif

}  // namespace
