// `illum bake --kind prt` and `illum relight`: a bake and relight that work, and
// bad input — band counts, kinds, modes, a folder baked for another scene, missing or
// corrupt folders, degenerate or non-finite sun directions — each one line, exit 2, and no
// output written.
#include <cmath>
#include <cstring>
#include <fstream>

#include "cli_fixture.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;
using illum_cli_test::slurp;

class PrtCli : public CliTest {
 protected:
  Result bake(const std::string& scene, const fs::path& folder, const std::string& extra = "") {
    return run("bake " + scene + " --kind prt --resolution 32 --spp 4 --bands 3 --seed 1 " + extra +
               " -o " + folder.string());
  }
  Result relight(const std::string& scene, const fs::path& folder, const std::string& light) {
    return run("relight " + scene + " --baked " + folder.string() + " " + light +
               " --width 16 --height 16 --spp 1 -o " + out().string());
  }
  fs::path out() const { return dir_ / "relit.png"; }
};

TEST_F(PrtCli, BakesAndRelightsUnderASunAndAnEnvironment) {
  const fs::path prt = dir_ / "prt";
  const Result b = bake("cornell", prt, "--mode interreflected");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  for (const char* file : {"prt.json", "atlas.bin", "texels.bin", "vertices.bin", "preview.png"})
    EXPECT_TRUE(fs::exists(prt / file)) << file;
  EXPECT_NE(slurp(prt / "prt.json").find("\"format\": \"illum-prt\""), std::string::npos);
  Result r = relight("cornell", prt, "--sun 0.3,-1,-0.5,2");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out()));
  fs::remove(out());
  r = relight("cornell", prt,
              "--sky " + std::string(ILLUM_SHARED_SCENES) +
                  "/envmaps/venice_sunset_1k.hdr --rotate 90 --lookup vertices");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out()));
  // The same geometry from another file is the same scene.
  fs::remove(out());
  r = relight(cornell_copy("copy", ""), prt, "--sun 0,-1,0");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(PrtCli, RefusesBadBakeOptions) {
  const fs::path prt = dir_ / "prt";
  expect_bad_input(run("bake cornell --kind prt --bands 1 -o " + prt.string()), "--bands");
  expect_bad_input(run("bake cornell --kind prt --bands 9 -o " + prt.string()), "--bands");
  expect_bad_input(run("bake cornell --kind nonsense -o " + prt.string()), "--kind");
  expect_bad_input(run("bake cornell --kind prt --mode sometimes -o " + prt.string()), "sometimes");
  expect_bad_input(run("bake cornell --bands 4 -o " + prt.string()), "--bands");  // lightmap kind
  expect_bad_input(run("bake cornell --kind prt --basis sh -o " + prt.string()), "--basis");
  expect_bad_input(run("bake cornell --kind prt --spp 0 -o " + prt.string()), "--spp");
  fs::create_directories(dir_ / "unrelated");
  std::ofstream(dir_ / "unrelated" / "keep.txt") << "mine";
  expect_bad_input(bake("cornell", dir_ / "unrelated"), "not a PRT folder");
  EXPECT_TRUE(fs::exists(dir_ / "unrelated" / "keep.txt"));
  EXPECT_FALSE(fs::exists(prt));
}

TEST_F(PrtCli, RefusesAFolderBakedForAnotherScene) {
  const fs::path prt = dir_ / "prt";
  ASSERT_EQ(bake("cornell", prt).exit_code, 0);
  // Same triangle count, moved by a millimetre: only the geometry hash tells them apart.
  const Result moved =
      relight(cornell_copy("moved", "{\"translate\": [0, 0.001, 0]}"), prt, "--sun 0,-1,0");
  expect_bad_input(moved, "baked for another scene");
  EXPECT_FALSE(fs::exists(out()));
  expect_bad_input(relight("caustics", prt, "--sun 0,-1,0"), "does not fit");
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(PrtCli, RefusesMissingAndCorruptFolders) {
  expect_bad_input(relight("cornell", dir_ / "nowhere", "--sun 0,-1,0"), "does not exist");
  fs::create_directories(dir_ / "empty");
  expect_bad_input(relight("cornell", dir_ / "empty", "--sun 0,-1,0"), "prt.json");
  const fs::path prt = dir_ / "prt";
  ASSERT_EQ(bake("cornell", prt).exit_code, 0);
  const std::string manifest = slurp(prt / "prt.json");
  std::ofstream(prt / "prt.json") << "{\"format\": ";
  expect_bad_input(relight("cornell", prt, "--sun 0,-1,0"), "prt.json");
  std::ofstream(prt / "prt.json") << manifest;
  const std::string texels = slurp(prt / "texels.bin");
  std::ofstream(prt / "texels.bin", std::ios::binary) << texels.substr(0, texels.size() - 4);
  expect_bad_input(relight("cornell", prt, "--sun 0,-1,0"), "texels.bin");
  std::string nan = texels;
  const float bad = NAN;
  std::memcpy(&nan[24 + 4 * 100], &bad, 4);
  std::ofstream(prt / "texels.bin", std::ios::binary) << nan;
  expect_bad_input(relight("cornell", prt, "--sun 0,-1,0"), "not finite");
  std::ofstream(prt / "texels.bin", std::ios::binary) << texels;
  std::string bands = manifest;
  bands.replace(bands.find("\"bands\": 3"), 10, "\"bands\": 9");
  std::ofstream(prt / "prt.json") << bands;
  expect_bad_input(relight("cornell", prt, "--sun 0,-1,0"), "bands");
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(PrtCli, RefusesBadLights) {
  const fs::path prt = dir_ / "prt";
  ASSERT_EQ(bake("cornell", prt).exit_code, 0);
  expect_bad_input(relight("cornell", prt, "--sun 0,0,0"), "--sun");
  expect_bad_input(relight("cornell", prt, "--sun nan,-1,0"), "--sun");
  expect_bad_input(relight("cornell", prt, "--sun 1,2"), "--sun");
  expect_bad_input(relight("cornell", prt, "--sun 0,-1,0,nan"), "--sun");
  expect_bad_input(relight("cornell", prt, ""), "--sun");
  expect_bad_input(relight("cornell", prt,
                           "--sun 0,-1,0 --sky " + std::string(ILLUM_SHARED_SCENES) +
                               "/envmaps/venice_sunset_1k.hdr"),
                   "exactly one light");
  expect_bad_input(relight("cornell", prt, "--sky " + (dir_ / "missing.hdr").string()),
                   "missing.hdr");
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(PrtCli, VqBakeRelightsAndRefusesBadIndices) {
  const fs::path prt = dir_ / "prt";
  const Result b = bake("cornell", prt, "--vq 16");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.err.find("VQ 16 representatives"), std::string::npos) << b.err;
  const Result r = relight("cornell", prt, "--sun 0,-1,0 --lookup vq");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  fs::remove(out());
  // An index past the representatives.
  std::string indices = slurp(prt / "vq_indices.bin");
  indices[20] = char(0xff);
  indices[21] = char(0xff);
  std::ofstream(prt / "vq_indices.bin", std::ios::binary) << indices;
  expect_bad_input(relight("cornell", prt, "--sun 0,-1,0 --lookup vq"), "vq_indices.bin");
  EXPECT_FALSE(fs::exists(out()));
  // A folder baked without --vq has nothing for --lookup vq.
  const fs::path plain = dir_ / "plain";
  ASSERT_EQ(bake("cornell", plain).exit_code, 0);
  expect_bad_input(relight("cornell", plain, "--sun 0,-1,0 --lookup vq"), "--vq");
  expect_bad_input(run("bake cornell --vq 16 -o " + (dir_ / "lm").string()), "--vq");
}

TEST_F(PrtCli, InterruptedBakeLeavesNoFolder) {
  const fs::path folder = dir_ / "prt";
  const std::string cmd = "sh -c '" + std::string(ILLUM_BINARY_DIR) +
                          "/bin/illum bake cornell --kind prt --mode interreflected --spp 1000000 "
                          "-o " +
                          folder.string() +
                          " 2>/dev/null & pid=$!; sleep 1; kill -INT $pid; wait $pid'";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++entries;
  EXPECT_EQ(entries, 0);
}

}  // namespace
