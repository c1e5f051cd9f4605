// Outputs that cannot reach the disk: a file-size limit (RLIMIT_FSIZE, with SIGXFSZ ignored,
// so write(2) fails with EFBIG exactly as a full disk fails with ENOSPC, and needs no root or
// tmpfs), an over-long file name, a folder that cannot hold files, and a bad second output.
// Each exits 2 with one line and leaves no file behind, neither the output nor a hidden
// temporary one.
#include <string>

#include "cli_fixture.h"

using namespace illum_cli_test;

namespace {

class DiskFullTest : public CliTest {
 protected:
  // `illum ARGS` in the test folder with files limited to `kib` KiB (ulimit -f counts
  // 512-byte blocks in dash, the /bin/sh std::system runs).
  Result run_limited(const std::string& args, int kib) {
    return run_command("sh -c \"cd " + dir_.string() + " && trap '' XFSZ && ulimit -f " +
                       std::to_string(kib * 2) + " && exec " + ILLUM_BINARY_DIR + "/bin/illum " +
                       args + "\"");
  }
  // Files the command left in the test folder, hidden ones included.
  std::vector<std::string> left() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n != "stdout.txt" && n != "stderr.txt") names.push_back(n);
    }
    return names;
  }
};

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += x + " ";
  return s;
}

TEST_F(DiskFullTest, RenderedImageThatDoesNotFitLeavesNothing) {
  // A 256² one-sample path-traced render: noise, so every format needs far more than the
  // 8 KiB the limit lets through.
  for (const std::string out : {"out.png", "out.jpg", "out.hdr", "out.exr"}) {
    const Result r = run_limited(
        "render cornell --integrator path --width 256 --height 256 --spp 1 -o " + out, 8);
    expect_bad_input(r, out);
    EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
    EXPECT_TRUE(left().empty()) << out << ": left " << joined(left());
  }
  // The control: the same command without the limit writes the file.
  const Result ok = run_limited(
      "render cornell --integrator path --width 256 --height 256 --spp 1 -o out.png", 1 << 20);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_GT(fs::file_size(dir_ / "out.png"), 8u * 1024u) << "the limited runs had to fail";
}

TEST_F(DiskFullTest, AtlasThatDoesNotFitLeavesNothing) {
  // The caustics scene's sphere makes an atlas file of hundreds of KiB while its 16² layer and
  // preview stay under 1 KiB: the atlas writer is the one that meets the 8 KiB limit.
  const std::string bake = "bake caustics --resolution 16 --spp 1 --seed 1 -o lm";
  const Result r = run_limited(bake, 8);
  expect_bad_input(r, "atlas.bin");
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_TRUE(left().empty()) << joined(left());
  const Result ok = run_limited(bake, 1 << 20);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_GT(fs::file_size(dir_ / "lm" / "atlas.bin"), 8u * 1024u) << "the limited run had to fail";
  EXPECT_LT(fs::file_size(dir_ / "lm" / "layer0.exr"), 8u * 1024u);
  EXPECT_LT(fs::file_size(dir_ / "lm" / "preview.png"), 8u * 1024u);
}

TEST_F(DiskFullTest, ExportThatDoesNotFitLeavesNothing) {
  ASSERT_EQ(run_limited("bake cornell --resolution 16 --spp 1 --seed 1 -o lm", 1 << 20).exit_code,
            0);
  const Result r = run_limited("export cornell --baked lm -o e.glb", 8);
  expect_bad_input(r, "e.glb");
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  fs::remove_all(dir_ / "lm");
  EXPECT_TRUE(left().empty()) << joined(left());
}

#ifdef ILLUM_HAVE_GPU  // `illum frame` exists only with the GPU layers
TEST_F(DiskFullTest, TechniqueListingThatDoesNotFitLeavesNothing) {
  const Result r = run_limited("frame --list --json list.json", 1);
  expect_bad_input(r, "list.json");
  EXPECT_TRUE(left().empty()) << joined(left());
  const Result ok = run_limited("frame --list --json list.json", 1 << 20);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_GT(fs::file_size(dir_ / "list.json"), 1024u) << "the limited run had to fail";
}

TEST_F(DiskFullTest, EveryOutputCheckedBeforeAnyIsWritten) {
  // The image's folder exists, the JSON's does not: refused before the frame, no image.
  const Result r = run("frame cornell -o " + (dir_ / "f.png").string() + " --json " +
                       (dir_ / "nodir" / "t.json").string());
  expect_bad_input(r, "nodir");
  EXPECT_TRUE(left().empty()) << joined(left());
}
#endif

TEST_F(DiskFullTest, UnwritableNamesAreOneLine) {
  const std::string long_name = std::string(300, 'a') + ".png";
  expect_bad_input(run("render cornell --integrator albedo --spp 1 -o " + long_name), "bytes");
  expect_bad_input(run("render cornell --integrator albedo --spp 1 -o /proc/x.png"), "/proc/x.png");
  expect_bad_input(run("render cornell --integrator albedo --spp 1 -o " + dir_.string() + "/"),
                   dir_.string());
  EXPECT_TRUE(left().empty()) << joined(left());
}

}  // namespace
