// `cmake --install`: the installed `illum` runs from any folder and finds its built-in
// scenes beside itself (<prefix>/share/illum), not in the checkout or the build tree.
#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class CliInstall : public CliTest {
 protected:
  // Installs the build tree into dir_/prefix and returns its `illum`.
  fs::path install() {
    const fs::path prefix = dir_ / "prefix";
    const Result r = run_command(std::string("cmake --install ") + ILLUM_BINARY_DIR + " --prefix " +
                                 prefix.string());
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    return prefix;
  }
  // Runs the installed program in dir_/elsewhere, a folder holding nothing of illum's.
  Result installed(const fs::path& prefix, const std::string& args) {
    fs::create_directories(dir_ / "elsewhere");
    return run_command("cd " + (dir_ / "elsewhere").string() + " && env -u ILLUM_DATA_DIR " +
                       (prefix / "bin" / "illum").string() + " " + args);
  }
};

TEST_F(CliInstall, InstalledProgramReadsItsOwnData) {
  const fs::path prefix = install();
  ASSERT_TRUE(fs::is_regular_file(prefix / "bin" / "illum"));
  ASSERT_TRUE(fs::is_regular_file(prefix / "share/illum/scenes/cornell/cornell.illum.json"));
  const Result info = installed(prefix, "info cornell --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const std::string source = nlohmann::json::parse(info.out).at("source");
  EXPECT_EQ(source.rfind((prefix / "share/illum/scenes/cornell").string(), 0), 0u)
      << "the installed illum read " << source;

  const Result render = installed(prefix, "render cornell --spp 1 --width 16 --height 16 -o r.png");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "elsewhere" / "r.png"));
}

#ifdef ILLUM_HAVE_GPU
// The real-time renderer's shaders are embedded in the program: a headless frame on lavapipe
// needs nothing from the build tree.
TEST_F(CliInstall, InstalledProgramDrawsAFrame) {
  const fs::path prefix = install();
  const Result frame = installed(prefix, "frame cornell --width 32 --height 32 -o f.png");
  ASSERT_EQ(frame.exit_code, 0) << frame.err;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "elsewhere" / "f.png"));
}
#endif

// The built-in sibenik's OBJ is not in the repository: when it is missing, one line says
// which path was looked in and how to provide it.
TEST_F(CliInstall, SibenikWithoutItsMeshSaysWhereItMustBe) {
  const fs::path empty = dir_ / "no-scenes";
  fs::create_directories(empty);
  const Result r = run_command("ILLUM_SHARED_SCENES=" + empty.string() + " " + ILLUM_BINARY_DIR +
                               "/bin/illum info sibenik");
  expect_bad_input(r, (empty / "sibenik/sibenik.obj").string());
  EXPECT_NE(r.err.find("set ILLUM_SHARED_SCENES"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace illum_cli_test
