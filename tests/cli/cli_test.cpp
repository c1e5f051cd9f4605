// Runs the real `illum` binary on good and bad input. Every bad input must give exit code
// 2, exactly one line on stderr that names the problem, and no output file.
#include "cli_fixture.h"
#include "test_support/prerequisites.h"

using namespace illum_cli_test;

namespace {

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST_F(CliTest, RendersCornellAo) {
  const fs::path out = dir_ / "ao.png";
  const auto r =
      run("render cornell --integrator ao --width 32 --height 32 --spp 4 -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  // Nothing but the image is left in the folder (no temporary files).
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.path().extension() == ".png";
  EXPECT_EQ(files, 1);
}

TEST_F(CliTest, InfoPrintsCounts) {
  const auto r = run("info cornell --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"triangles\": 32"), std::string::npos) << r.out;
}

TEST_F(CliTest, MissingSceneFile) {
  const auto missing = (dir_ / "nope.obj").string();
  expect_bad_input(run("info " + missing), "nope.obj");
}

TEST_F(CliTest, MalformedJsonScene) {
  const auto p = write("bad.illum.json", "{ \"meshes\": [ { \"file\": \"x.obj\" } ");
  expect_bad_input(run("info " + p.string()), "bad.illum.json");
}

TEST_F(CliTest, UnknownJsonKey) {
  write("tri.obj", kTriangleObj);
  const auto p = write("typo.illum.json", R"({"meshes": [{"file": "tri.obj"}], "lihgts": []})");
  expect_bad_input(run("info " + p.string()), "lihgts");
}

TEST_F(CliTest, MalformedGltf) {
  const auto truncated = write("truncated.gltf", R"({"asset": {"version": "2.0"}, "meshes": [ )");
  expect_bad_input(run("info " + truncated.string()), "truncated.gltf");
  // Well-formed JSON, but the position attribute names an accessor that does not exist.
  const auto dangling = write("dangling.gltf", R"({"asset": {"version": "2.0"}, "scene": 0,
    "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 5}}]}]})");
  expect_bad_input(run("info " + dangling.string()), "dangling.gltf");
}

TEST_F(CliTest, SponzaWithoutBufferFailsCleanly) {
  ILLUM_REQUIRE_SHARED_SCENE("sponza/glTF/Sponza.gltf");
  const std::string sponza = ::illum::test::shared_scene("sponza/glTF/Sponza.gltf");
  expect_bad_input(run("info " + sponza), "missing buffer");
}

TEST_F(CliTest, UnknownCliOption) {
  expect_bad_input(
      run("render cornell --integrator ao --frobnicate 3 -o " + (dir_ / "x.png").string()),
      "frobnicate");
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(CliTest, UnknownIntegrator) {
  const fs::path out = dir_ / "x.png";
  expect_bad_input(run("render cornell --integrator magic -o " + out.string()), "magic");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliTest, UnknownIntegratorParam) {
  const fs::path out = dir_ / "x.png";
  expect_bad_input(run("render cornell --integrator ao --param colour=3 -o " + out.string()),
                   "colour");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliTest, NanVertex) {
  const auto p = write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_bad_input(run("info " + p.string()), "nan.obj");
}

TEST_F(CliTest, InfVertex) {
  const auto p = write("inf.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_bad_input(run("info " + p.string()), "inf.obj");
}

TEST_F(CliTest, DegenerateTrianglesDroppedWithOneWarning) {
  // Two good triangles, three degenerate ones (repeated index, collinear, coincident).
  const auto p = write("degen.obj",
                       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\nv 0 0 0\n"
                       "f 1 2 3\nf 2 4 3\nf 1 1 2\nf 1 2 5\nf 1 6 2\n");
  const auto r = run("info --json " + p.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"triangles\": 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 degenerate"), std::string::npos) << r.out;
}

TEST_F(CliTest, OutputInMissingFolder) {
  const fs::path out = dir_ / "no" / "such" / "folder" / "x.png";
  expect_bad_input(run("render cornell --integrator ao --spp 1 -o " + out.string()),
                   "does not exist");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliTest, UnknownOutputExtension) {
  const fs::path out = dir_ / "x.bmpx";
  expect_bad_input(run("render cornell --integrator ao -o " + out.string()), "x.bmpx");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliTest, ZeroSamplesAndAbsurdResolution) {
  const fs::path out = dir_ / "x.png";
  expect_bad_input(run("render cornell --integrator ao --spp 0 -o " + out.string()), "spp");
  expect_bad_input(run("render cornell --integrator ao --width 100000 -o " + out.string()),
                   "width");
  EXPECT_FALSE(fs::exists(out));
}

// Ctrl-C during a long render: exit 130, no output file, for a tile integrator and for the
// photon-based ones, whose loops are not tiles.
TEST_F(CliTest, InterruptStopsCleanlyWithoutOutput) {
  for (const std::string integrator : {"path", "sppm", "photon"}) {
    const fs::path out = dir_ / ("int-" + integrator + ".png");
    const std::string params = integrator == "sppm"     ? "-p iterations=1000000"
                               : integrator == "photon" ? "-p photons=100000000"
                                                        : "--spp 1000000";
    const std::string cmd = "sh -c '" + std::string(ILLUM_BINARY_DIR) +
                            "/bin/illum render cornell -i " + integrator + " " + params + " -o " +
                            out.string() +
                            " 2>/dev/null & pid=$!; sleep 1; kill -INT $pid; wait $pid'";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << integrator;
    EXPECT_EQ(WEXITSTATUS(status), 130) << integrator;
    EXPECT_FALSE(fs::exists(out)) << integrator;
  }
}

// `illum bake` writes a complete light-map folder and nothing else; `illum frame
// --baked` shows it.
TEST_F(CliTest, BakeWritesALightmapFolderThatFrameShows) {
  const fs::path folder = dir_ / "cornell-lm";
  const auto r = run("bake cornell --resolution 32 --spp 2 --basis sh -o " + folder.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"lightmap.json", "atlas.bin", "layer0.exr", "layer1.exr", "layer2.exr",
                           "layer3.exr", "preview.png"})
    EXPECT_TRUE(fs::exists(folder / name)) << name;
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir_))
    entries += e.path() != dir_ / "stdout.txt" && e.path() != dir_ / "stderr.txt";
  EXPECT_EQ(entries, 1) << "only the folder, no staging leftovers";
  const std::string manifest = slurp(folder / "lightmap.json");
  EXPECT_NE(manifest.find("\"basis\": \"sh\""), std::string::npos) << manifest;
  // Baking again over an earlier light-map folder replaces it (a trailing '/' names the
  // same folder).
  ASSERT_EQ(run("bake cornell --resolution 32 --spp 2 -o " + folder.string() + "/").exit_code, 0);
  EXPECT_FALSE(fs::exists(folder / "layer1.exr")) << "the plain set has one layer";
#ifdef ILLUM_HAVE_GPU
  const fs::path frame = dir_ / "frame.png";
  const auto f = run("frame cornell --width 32 --height 32 --baked " + folder.string() + " -o " +
                     frame.string());
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_TRUE(fs::exists(frame));
#endif
}

TEST_F(CliTest, BakeRefusesBadOptionsAndOutputs) {
  const fs::path folder = dir_ / "lm";
  expect_bad_input(run("bake cornell --resolution 8 -o " + folder.string()), "resolution");
  expect_bad_input(run("bake cornell --spp 0 -o " + folder.string()), "spp");
  expect_bad_input(run("bake cornell --basis wavelet -o " + folder.string()), "basis");
  expect_bad_input(run("bake cornell --content direct -o " + folder.string()), "content");
  expect_bad_input(run("bake cornell -o " + (dir_ / "no" / "lm").string()), "does not exist");
  expect_bad_input(run("bake cornell --resolution 16 --texel-size 0.5 -o " + folder.string()),
                   "16");
  EXPECT_FALSE(fs::exists(folder));
  // An existing folder that is not a light-map folder is never replaced.
  fs::create_directories(dir_ / "mine");
  write("mine/notes.txt", "keep me");
  expect_bad_input(run("bake cornell --spp 1 -o " + (dir_ / "mine").string()),
                   "not a light-map folder");
  EXPECT_EQ(slurp(dir_ / "mine" / "notes.txt"), "keep me");
}

#ifdef ILLUM_HAVE_GPU
TEST_F(CliTest, FrameRefusesBadLightmapFolders) {
  const fs::path frame = dir_ / "frame.png";
  expect_bad_input(
      run("frame cornell --baked " + (dir_ / "none").string() + " -o " + frame.string()),
      "does not exist");
  const fs::path folder = dir_ / "lm";
  ASSERT_EQ(run("bake cornell --resolution 32 --spp 1 -o " + folder.string()).exit_code, 0);
  // Baked for another scene.
  write("tri.obj", kTriangleObj);
  expect_bad_input(run("frame " + (dir_ / "tri.obj").string() + " --baked " + folder.string() +
                       " -o " + frame.string()),
                   "does not fit");
  // A malformed manifest, then a missing layer.
  const std::string manifest = slurp(folder / "lightmap.json");
  write("lm/lightmap.json", manifest.substr(0, manifest.size() / 2));
  expect_bad_input(run("frame cornell --baked " + folder.string() + " -o " + frame.string()),
                   "malformed");
  write("lm/lightmap.json", manifest);
  fs::remove(folder / "layer0.exr");
  expect_bad_input(run("frame cornell --baked " + folder.string() + " -o " + frame.string()),
                   "layer0.exr");
  EXPECT_FALSE(fs::exists(frame));
}
#endif

// Ctrl-C during a bake: exit 130 and no folder (not even a staging one).
TEST_F(CliTest, InterruptedBakeLeavesNoFolder) {
  const fs::path folder = dir_ / "lm";
  const std::string cmd = "sh -c '" + std::string(ILLUM_BINARY_DIR) +
                          "/bin/illum bake cornell --spp 1000000 -o " + folder.string() +
                          " 2>/dev/null & pid=$!; sleep 1; kill -INT $pid; wait $pid'";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++entries;
  EXPECT_EQ(entries, 0);
}

TEST_F(CliTest, NoSubcommand) {
  const auto r = run("");
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
