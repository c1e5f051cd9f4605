// Distributed runs: `mpirun -np N illum render|bake` splits tiles and
// texels over N ranks and gives the same bytes as one process for N = 1, 2, 3; threads per
// rank default to the node's cores over its ranks; what cannot be split is refused with
// exit 2; a rank that dies or a Ctrl-C to mpirun ends the job with no output.
// mpirun is the one FindMPI found at configure time (ILLUM_MPIEXEC); a missing one fails the
// tests, in CI or not. CI runs as root, which Open MPI refuses unless told otherwise.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <regex>
#include <sstream>
#include <thread>
#include <vector>

#include "cli_fixture.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;
using illum_cli_test::slurp;

constexpr const char* kAllowRoot = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1";
// The asan preset: Open MPI 4.1.4 leaves allocations behind after MPI_Finalize (in
// ompi_op_base_op_select and in its dlopen'ed components, which LeakSanitizer cannot even
// name), so every rank would fail on leaks not its own. Leak checks stay off for the ranks
// only; AddressSanitizer and UBSan errors still fail them, and every other test runs the
// same render and bake code without MPI with leak checks on.
constexpr const char* kNoLeakChecks = "ASAN_OPTIONS=detect_leaks=0";

class MpiCli : public CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    ASSERT_TRUE(fs::exists(ILLUM_MPIEXEC)) << "mpirun not found: " << ILLUM_MPIEXEC
                                           << " (scripts/install-deps.sh installs openmpi-bin)";
  }
  // The command line that starts `args` on `ranks` ranks. -q keeps mpirun's own banners out
  // of stderr, so the lines checked are illum's.
  std::string mpirun_command(int ranks, const std::string& args, const std::string& env = "",
                             const std::string& mpirun_options = "-q") {
    return std::string("env ") + kAllowRoot + " " + kNoLeakChecks + " " + env + " " +
           ILLUM_MPIEXEC + " --oversubscribe " + mpirun_options + " -np " + std::to_string(ranks) +
           " " + ILLUM_BINARY_DIR + "/bin/illum " + args;
  }
  Result mpirun(int ranks, const std::string& args, const std::string& env = "",
                const std::string& mpirun_options = "-q") {
    return run_command(mpirun_command(ranks, args, env, mpirun_options));
  }
  // Files in the test folder other than the captured stdout/stderr: outputs, and any
  // temporary file a killed writer left.
  std::vector<std::string> outputs() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      if (name.find("stdout.txt") == std::string::npos &&
          name.find("stderr.txt") == std::string::npos)
        names.push_back(name);
    }
    return names;
  }
  // The items each rank computed, from rank 0's "distributed: K items over N ranks (a / b)"
  // lines (--log info), one vector per split loop.
  static std::vector<std::vector<long>> items_per_rank(const std::string& err, long* total) {
    std::vector<std::vector<long>> loops;
    const std::regex line(R"(distributed: (\d+) items over \d+ ranks \(([0-9 /]+)\))");
    for (auto it = std::sregex_iterator(err.begin(), err.end(), line); it != std::sregex_iterator();
         ++it) {
      *total = std::stol((*it)[1].str());
      std::vector<long> counts;
      std::stringstream list((*it)[2].str());
      for (std::string item; std::getline(list, item, '/');) counts.push_back(std::stol(item));
      loops.push_back(counts);
    }
    return loops;
  }
  // Work was really split: every item once, and ranks other than 0 computed some.
  static void expect_split(const Result& r, int ranks, long items) {
    long total = 0;
    const auto loops = items_per_rank(r.err, &total);
    ASSERT_FALSE(loops.empty()) << r.err;
    for (const std::vector<long>& counts : loops) {
      ASSERT_EQ(counts.size(), static_cast<size_t>(ranks)) << r.err;
      long sum = 0, others = 0;
      for (size_t k = 0; k < counts.size(); ++k) {
        sum += counts[k];
        if (k > 0) others += counts[k];
      }
      if (items > 0) {
        EXPECT_EQ(sum, items) << r.err;
      }
      EXPECT_GT(others, 0) << "only rank 0 worked: " << r.err;
    }
  }
};

// 96×80 pixels are 6×5 = 30 tiles of 16, the last row cut; 24 spp spans the passes 1, 1,
// 2, 4, 8, 8 whose sums the tile path must repeat in the same order.
constexpr const char* kRender =
    "--log info render cornell --width 96 --height 80 --spp 24 --seed 7 --no-preview -o ";

TEST_F(MpiCli, RenderIsTheSameBytesOnOneTwoAndThreeRanks) {
  const Result one = run(std::string(kRender) + (dir_ / "plain.exr").string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const std::string reference = slurp(dir_ / "plain.exr");
  ASSERT_FALSE(reference.empty());
  for (int ranks = 1; ranks <= 3; ++ranks) {
    const fs::path out = dir_ / ("ranks" + std::to_string(ranks) + ".exr");
    const Result r = mpirun(ranks, std::string(kRender) + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(slurp(out) == reference) << ranks << " ranks gave other bytes";
    if (ranks > 1) expect_split(r, ranks, 30);
  }
}

TEST_F(MpiCli, BakeWithDenoiserAndExtrasIsTheSameBytesOnOneTwoAndThreeRanks) {
  // Work enough in both loops (about 0.2 s each on one core) that every rank gets some
  // even when the others start late on a loaded machine.
  const std::string bake =
      "--log info bake cornell --resolution 48 --spp 64 --seed 3 --extras ao,obscurance,"
      "bent_normal --extras-rays 256 -o ";
  const Result one = run(bake + (dir_ / "plain").string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  // The manifest holds timings; its counts must agree.
  auto counts = [](const std::string& manifest) {
    std::string found;
    const std::regex key(R"re("(rays|extras_rays|texels|denoise)": ([0-9a-z]+))re");
    for (auto it = std::sregex_iterator(manifest.begin(), manifest.end(), key);
         it != std::sregex_iterator(); ++it)
      found += (*it)[0].str() + "\n";
    return found;
  };
  const std::string reference_counts = counts(slurp(dir_ / "plain" / "lightmap.json"));
  EXPECT_NE(reference_counts.find("\"denoise\": true"), std::string::npos) << reference_counts;
  for (int ranks = 1; ranks <= 3; ++ranks) {
    const fs::path out = dir_ / ("ranks" + std::to_string(ranks));
    const Result r = mpirun(ranks, bake + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    int compared = 0;
    for (const auto& entry : fs::directory_iterator(dir_ / "plain")) {
      const std::string name = entry.path().filename().string();
      if (name == "lightmap.json") continue;
      EXPECT_TRUE(slurp(entry.path()) == slurp(out / name))
          << ranks << " ranks gave other bytes in " << name;
      ++compared;
    }
    EXPECT_GE(compared, 6);  // atlas, layer, preview, ao, obscurance ×2, bent normal
    EXPECT_EQ(counts(slurp(out / "lightmap.json")), reference_counts);
    if (ranks > 1) {
      expect_split(r, ranks, 0);
      long total = 0;
      EXPECT_EQ(items_per_rank(r.err, &total).size(), 2u) << "the layers and the extras: " << r.err;
    }
  }
}

TEST_F(MpiCli, ThreadsPerRankAreTheNodesCoresOverItsRanksUnlessGiven) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::string args = "--log info render cornell --width 32 --height 32 --spp 1 -o ";
  for (int ranks = 1; ranks <= 3; ++ranks) {
    const Result r = mpirun(ranks, args + (dir_ / "a.png").string(), "", "-q --bind-to none");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // One node: every rank is on it.
    const std::string expected = "distributed: " + std::to_string(ranks) + " ranks, " +
                                 std::to_string(ranks) + " on this node, " +
                                 std::to_string(std::max(1, cores / ranks)) +
                                 " threads per rank by default";
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in\n"
                                                       << r.err;
  }
  // --threads wins: rank 0 ran its share on that many threads (one that differs from the
  // default, and that the machine has when it has two cores).
  const int given_threads = std::max(1, cores / 2) == 1 ? 2 : 1;
  const Result given =
      mpirun(2,
             "--log info render cornell --width 32 --height 32 --spp 4 "
             "--threads " +
                 std::to_string(given_threads) + " -o " + (dir_ / "b.png").string(),
             "", "-q --bind-to none");
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_NE(given.err.find("), " + std::to_string(given_threads) + " threads on rank 0"),
            std::string::npos)
      << given.err;
}

TEST_F(MpiCli, WhatCannotBeSplitIsRefusedOnSeveralRanks) {
  const fs::path out = dir_ / "out.png";
  const std::string small = " --width 16 --height 16 --spp 2 -o " + out.string();
  const Result time = mpirun(2, "render cornell --time 1" + small);
  EXPECT_EQ(time.exit_code, 2) << time.err;
  EXPECT_EQ(time.err_lines(), 1) << time.err;
  EXPECT_NE(time.err.find("illum: error: --time 1 cannot run on 2 MPI ranks"), std::string::npos)
      << time.err;
  const Result sppm = mpirun(3, "render cornell -i sppm" + small);
  EXPECT_EQ(sppm.exit_code, 2) << sppm.err;
  EXPECT_EQ(sppm.err_lines(), 1) << sppm.err;
  EXPECT_NE(sppm.err.find("illum: error: --integrator sppm cannot run on 3 MPI ranks"),
            std::string::npos)
      << sppm.err;
  // The sequential bakers: radiosity's and PRT's shooting loops run over every patch.
  const Result radiosity =
      mpirun(3, "bake cornell --method radiosity --resolution 16 -o " + (dir_ / "lm").string());
  EXPECT_EQ(radiosity.exit_code, 2) << radiosity.err;
  EXPECT_EQ(radiosity.err_lines(), 1) << radiosity.err;
  EXPECT_NE(radiosity.err.find("illum: error: bake --method radiosity cannot run on 3 MPI ranks"),
            std::string::npos)
      << radiosity.err;
  const Result prt =
      mpirun(3, "bake cornell --kind prt --resolution 16 -o " + (dir_ / "prt").string());
  EXPECT_EQ(prt.exit_code, 2) << prt.err;
  EXPECT_EQ(prt.err_lines(), 1) << prt.err;
  EXPECT_NE(prt.err.find("illum: error: bake --kind prt cannot run on 3 MPI ranks"),
            std::string::npos)
      << prt.err;
  EXPECT_TRUE(outputs().empty());
  // One rank is one process: nothing to refuse.
  const Result alone = mpirun(1, "render cornell --time 1" + small);
  EXPECT_EQ(alone.exit_code, 0) << alone.err;
  EXPECT_TRUE(fs::exists(out));
}

TEST_F(MpiCli, ARankThatDiesEndsTheJobWithNoOutput) {
  // ILLUM_TEST_ABORT_RANK (test-only, distributed/README.md): that rank aborts before asking
  // for its first unit, so rank 0 can never finish the loop on its own.
  for (const std::string& args :
       {"render cornell --width 64 --height 64 --spp 4 -o " + (dir_ / "out.png").string(),
        "bake cornell --resolution 32 --spp 2 -o " + (dir_ / "lm").string()}) {
    const Result r = mpirun(2, args, "ILLUM_TEST_ABORT_RANK=1", "");  // with mpirun's report
    EXPECT_NE(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("process rank 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("signal 6"), std::string::npos) << r.err;
    EXPECT_TRUE(outputs().empty()) << args << " left " << outputs().front();
  }
}

TEST_F(MpiCli, CtrlCToMpirunEndsTheJobWithNoOutput) {
  const fs::path out = dir_ / "out.png";
  // Minutes of work: the interrupt lands during the render, whatever the machine's load.
  const std::string cmd = "exec " +
                          mpirun_command(2,
                                         "render cornell --width 128 --height 128 "
                                         "--spp 100000 -o " +
                                             out.string()) +
                          " >" + (dir_ / "mpirun-stdout.txt").string() + " 2>" +
                          (dir_ / "mpirun-stderr.txt").string() + " </dev/null";
  int status = 0;
  ASSERT_TRUE(signal_and_wait(cmd, std::chrono::milliseconds(2000), SIGINT,
                              std::chrono::seconds(30), &status))
      << "mpirun did not end within 30 s of SIGINT";
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_TRUE(outputs().empty()) << "left " << outputs().front();
}

// Bad input every rank sees: the ranks agree before any output, rank 0 alone prints, and
// every rank ends through MPI_Finalize with exit code 2. mpirun -q (what MpiCli runs) adds
// nothing, so stderr is exactly illum's one line, unfiltered.
TEST_F(MpiCli, BadInputOnThreeRanksIsOneLine) {
  const std::string out = (dir_ / "out.png").string();
  const struct {
    std::string args, env, needle;
  } cases[] = {
      {"render cornell --spp 0 -o " + out, "", "--spp"},
      {"render no-such-scene --spp 1 -o " + out, "", "no-such-scene"},
      {"render cornell --spp 1 -o " + (dir_ / "nodir" / "x.png").string(), "", "nodir"},
      {"render cornell --bogus-option -o " + out, "", "--bogus-option"},
      {"render cornell --spp 1 -o " + out, "ILLUM_RANK_TIMEOUT=soon", "ILLUM_RANK_TIMEOUT"},
      {"relight cornell -o " + out, "", "relight"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args + " " + c.env);
    const Result r = mpirun(3, c.args, c.env);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err_lines(), 1) << r.err;
    EXPECT_EQ(r.err.rfind("illum: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << r.err;
    EXPECT_TRUE(outputs().empty()) << "left " << outputs().front();
  }
}

// The rank (pid) of `mpirun`'s child process whose OMPI_COMM_WORLD_RANK is `rank`, or -1.
pid_t rank_pid(pid_t mpirun, int rank) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = slurp(entry.path() / "stat");
    const size_t paren = stat.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream fields(stat.substr(paren + 2));
    std::string state;
    pid_t parent = 0;
    fields >> state >> parent;
    if (parent != mpirun) continue;
    const std::string env = slurp(entry.path() / "environ");
    if (env.find(std::string("OMPI_COMM_WORLD_RANK=") + std::to_string(rank) + '\0') !=
        std::string::npos)
      return static_cast<pid_t>(std::stol(name));
  }
  return -1;
}

// A rank stopped with SIGSTOP sends no heartbeat: within ILLUM_RANK_TIMEOUT (5 s here) the
// others end the job with one line and a non-zero exit, writing nothing.
TEST_F(MpiCli, AStoppedRankEndsTheJobWithinTheTimeout) {
  constexpr int kTimeout = 5;
  constexpr int kMargin = 20;  // start-up of the ranks and a loaded machine
  for (const int stopped : {2, 0}) {
    SCOPED_TRACE("stopped rank " + std::to_string(stopped));
    const fs::path out = dir_ / "out.png", err = dir_ / "mpirun-stderr.txt";
    const std::string cmd =
        "exec " +
        mpirun_command(3, "render cornell --width 128 --height 128 --spp 100000 -o " + out.string(),
                       "ILLUM_RANK_TIMEOUT=" + std::to_string(kTimeout)) +
        " >/dev/null 2>" + err.string() + " </dev/null";
    const pid_t pid = start_command(cmd);
    ASSERT_GT(pid, 0);
    pid_t rank = -1;
    for (int i = 0; i < 300 && rank < 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      rank = rank_pid(pid, stopped);
    }
    ASSERT_GT(rank, 0) << "rank " << stopped << " did not start";
    std::this_thread::sleep_for(std::chrono::seconds(2));  // the render is under way
    ASSERT_EQ(kill(rank, SIGSTOP), 0);
    const auto start = std::chrono::steady_clock::now();
    int status = 0;
    const bool ended = wait_for(pid, std::chrono::seconds(kTimeout + kMargin), &status);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    kill(rank, SIGCONT);  // if mpirun left it (it does not), let SIGKILL below reach it
    kill(rank, SIGKILL);
    ASSERT_TRUE(ended) << "the job did not end within " << kTimeout + kMargin << " s";
    EXPECT_GE(seconds, kTimeout - 1.0) << "ended before the timeout";
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    const std::string text = slurp(err);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
    EXPECT_NE(text.find("illum: error: rank " + std::to_string(stopped) + " sent no sign of life"),
              std::string::npos)
        << text;
    fs::remove(err);
    EXPECT_TRUE(outputs().empty()) << "left " << outputs().front();
  }
}

}  // namespace
