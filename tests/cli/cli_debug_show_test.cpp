// Technique dependencies and `-p debug.show` at the CLI: the listing names each technique's
// dependencies, switching off what an add-on on needs is one line with exit code 2, and an
// unknown resource is one line listing the frame's images, with no output file.
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliDebugShow : public CliTest {};

// `illum frame` exists only where the GPU layers are built (not in the asan tree).
#ifdef ILLUM_HAVE_GPU
TEST_F(CliDebugShow, ListingNamesTheDependencies) {
  const Result r = run("frame --list --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  bool debug = false;
  for (const auto& t : j.at("techniques")) {
    ASSERT_TRUE(t.contains("dependencies")) << t.dump();
    if (t["name"] == "debug") {
      debug = true;
      EXPECT_EQ(t["dependencies"], nlohmann::json::array({"tonemap"}));
    } else if (t["name"] == "lpv" || t["name"] == "vpl") {
      EXPECT_EQ(t["dependencies"], nlohmann::json::array({"rsm"}));
    } else {
      EXPECT_TRUE(t["dependencies"].empty()) << t["name"];
    }
  }
  EXPECT_TRUE(debug);
  const Result text = run("frame --list");
  EXPECT_NE(text.out.find("    needs: tonemap (switched on with it)"), std::string::npos);
}

TEST_F(CliDebugShow, SwitchingOffWhatIsNeededIsOneLineExitTwo) {
  const Result r = run("frame cornell --width 16 --height 16 --enable debug --disable tonemap -o " +
                       (dir_ / "f.png").string());
  expect_bad_input(r, "--disable tonemap: 'debug' needs 'tonemap'");
  EXPECT_FALSE(fs::exists(dir_ / "f.png"));
}

TEST_F(CliDebugShow, UnknownResourceListsTheImagesExitTwo) {
  const Result r = run("frame cornell --width 16 --height 16 -p debug.show=nosuch -o " +
                       (dir_ / "f.png").string());
  expect_bad_input(r, "no image 'nosuch' (images of this frame: ");
  EXPECT_NE(r.err.find("depth"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "f.png"));
  for (const std::string bad : {"depth:x", "hdr:0:1", ":0"}) {
    const Result b = run("frame cornell --width 16 --height 16 -p debug.show=" + bad + " -o " +
                         (dir_ / "f.png").string());
    expect_bad_input(b, "-p debug.show=" + bad + ": ");
    EXPECT_FALSE(fs::exists(dir_ / "f.png")) << bad;
  }
}

TEST_F(CliDebugShow, ShowsADeclaredImage) {
  const Result r = run("frame cornell --width 16 --height 16 -p debug.show=depth -o " +
                       (dir_ / "f.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "f.png"));
}
#endif

}  // namespace
}  // namespace illum_cli_test
