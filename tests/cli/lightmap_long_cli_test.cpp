// Long light-map bakes through `illum bake`: `--time` for the path
// baker (passes of doubling samples, the samples taken in the manifest), Ctrl-C during both
// bakers (exit 130, nothing written), the peak-memory refusal (seen here through
// ILLUM_MEMORY_LIMIT, so no huge machine is needed), a scene with nothing to bake and an
// unknown extra map: one line, exit 2, nothing written.
#include <sys/wait.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace illum_cli_test {
namespace {

class LightmapLongCli : public CliTest {
 protected:
  void expect_nothing_written() {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "stdout.txt" || name == "stderr.txt" || name.ends_with(".obj"))
          << "left behind: " << entry.path();
    }
  }
  // Runs `illum ARGS` in the background, sends SIGINT after a second, returns the exit code.
  int interrupted(const std::string& args) {
    const std::string cmd = "sh -c '" + std::string(ILLUM_BINARY_DIR) + "/bin/illum " + args +
                            " 2>/dev/null & pid=$!; sleep 1; kill -INT $pid; wait $pid'";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  void TearDown() override {
    unsetenv("ILLUM_MEMORY_LIMIT");
    CliTest::TearDown();
  }
};

// 2^20 samples per texel would take hours: the bake stops by the budget after a whole pass
// and says how many samples it took.
TEST_F(LightmapLongCli, PathTimeStopsAfterWholePasses) {
  const fs::path out = dir_ / "lm";
  const Result r = run("bake cornell --resolution 32 --spp 1048576 --time 1 -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("stopped by --time"), std::string::npos) << r.err;
  const nlohmann::json m = nlohmann::json::parse(slurp(out / "lightmap.json")).at("bake");
  const int spp = m.at("spp").get<int>();
  EXPECT_GE(spp, 1);
  EXPECT_LT(spp, 1048576);
  EXPECT_EQ(spp & (spp - 1), 0) << spp;  // a whole pass: a power of two
  EXPECT_EQ(m.at("spp_requested").get<int>(), 1048576);
  EXPECT_TRUE(m.at("stopped_by_time").get<bool>());
  EXPECT_DOUBLE_EQ(m.at("time_budget").get<double>(), 1.0);
}

// A budget never reached: the raw maps are those of the bake without --time, byte for byte.
TEST_F(LightmapLongCli, PathTimeNotReachedGivesTheSameMaps) {
  const std::string bake = "bake cornell --resolution 32 --spp 8 --basis rnm -p denoise=false ";
  ASSERT_EQ(run(bake + "-o " + (dir_ / "a").string()).exit_code, 0);
  const Result r = run(bake + "--time 1000 -o " + (dir_ / "b").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* layer : {"layer0.exr", "layer1.exr", "layer2.exr"})
    EXPECT_EQ(slurp(dir_ / "a" / layer), slurp(dir_ / "b" / layer)) << layer;
  const nlohmann::json m = nlohmann::json::parse(slurp(dir_ / "b" / "lightmap.json")).at("bake");
  EXPECT_EQ(m.at("spp").get<int>(), 8);
  EXPECT_EQ(m.at("passes").get<int>(), 4);
  EXPECT_FALSE(m.at("stopped_by_time").get<bool>());
}

TEST_F(LightmapLongCli, PathTimeRefusals) {
  const std::string bake = "bake cornell --resolution 32 -o " + (dir_ / "lm").string() + " ";
  expect_bad_input(run(bake + "--spp 100 --time 5"), "--spp 100 with --time");
  expect_bad_input(run(bake + "--time -1"), "--time");
  expect_bad_input(run(bake + "--time nan"), "--time");
  expect_bad_input(run(bake + "--threshold 0.01"), "--threshold applies to --method radiosity");
  expect_nothing_written();
}

TEST_F(LightmapLongCli, CtrlCStopsBothBakersWithoutOutput) {
  const std::string out = " -o " + (dir_ / "lm").string();
  EXPECT_EQ(interrupted("bake cornell --resolution 64 --spp 1048576 --time 1000" + out), 130);
  expect_nothing_written();
  EXPECT_EQ(interrupted("bake cornell --method radiosity --resolution 256 --threshold 1e-6" + out),
            130);
  expect_nothing_written();
}

// The machine limit lowered to 20 MiB: a 1024² bake (about 140 MB) is refused before the
// raster with the estimate and the limit; a 32² one (about 16 MB) still runs.
TEST_F(LightmapLongCli, BakeOverTheMemoryLimitIsRefused) {
  ASSERT_EQ(setenv("ILLUM_MEMORY_LIMIT", "20M", 1), 0);
  const fs::path out = dir_ / "lm";
  const Result r = run("bake cornell --resolution 1024 --spp 1 -o " + out.string());
  expect_bad_input(r, "bake needs about");
  EXPECT_NE(r.err.find("ILLUM_MEMORY_LIMIT 20 MiB"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1048576 atlas texels"), std::string::npos) << r.err;
  expect_nothing_written();
  expect_bad_input(run("bake cornell --method radiosity --resolution 1024 -o " + out.string()),
                   "bake needs about");
  expect_nothing_written();
  const Result small = run("bake cornell --resolution 32 --spp 1 -o " + out.string());
  EXPECT_EQ(small.exit_code, 0) << small.err;
  fs::remove_all(out);
  ASSERT_EQ(setenv("ILLUM_MEMORY_LIMIT", "plenty", 1), 0);
  expect_bad_input(run("bake cornell --resolution 32 --spp 1 -o " + out.string()),
                   "ILLUM_MEMORY_LIMIT 'plenty'");
  expect_nothing_written();
}

// Only zero-area triangles (collinear, repeated corners): nothing can be baked.
TEST_F(LightmapLongCli, NothingToBakeIsRefused) {
  const fs::path scene =
      write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 4\n");
  for (const char* method : {"path", "radiosity"}) {
    expect_bad_input(run("bake " + scene.string() + " --method " + method + " --resolution 32 -o " +
                         (dir_ / "lm").string()),
                     "nothing to bake");
    expect_nothing_written();
  }
}

// `--time` on several MPI ranks: refused as `render --time` (the passes a rank finishes in the
// time would depend on the ranks); `--spp` alone still splits (mpi_cli_test.cpp).
TEST_F(LightmapLongCli, PathTimeIsRefusedOnSeveralRanks) {
  ASSERT_TRUE(fs::exists(ILLUM_MPIEXEC)) << "mpirun not found: " << ILLUM_MPIEXEC;
  const std::string cmd = std::string(
                              "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                              "ASAN_OPTIONS=detect_leaks=0 ") +
                          ILLUM_MPIEXEC + " --oversubscribe -q -np 2 " + ILLUM_BINARY_DIR +
                          "/bin/illum bake cornell --resolution 16 --time 5 -o " +
                          (dir_ / "lm").string() + " >" + (dir_ / "stdout.txt").string() + " 2>" +
                          (dir_ / "stderr.txt").string() + " </dev/null";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string err = slurp(dir_ / "stderr.txt");
  EXPECT_NE(err.find("illum: error: --time 5 cannot run on 2 MPI ranks"), std::string::npos) << err;
  expect_nothing_written();
}

TEST_F(LightmapLongCli, UnknownExtraMapIsRefused) {
  expect_bad_input(
      run("bake cornell --resolution 32 --spp 1 --extras ao,glow -o " + (dir_ / "lm").string()),
      "unknown extra map 'glow'");
  expect_nothing_written();
}

}  // namespace
}  // namespace illum_cli_test
