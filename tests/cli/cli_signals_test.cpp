// `illum` stopped by a signal: SIGTERM and SIGHUP end a render as Ctrl-C does — exit 130,
// one line naming the signal, no output and no hidden temporary file.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "cli_fixture.h"

using namespace illum_cli_test;

namespace {

TEST_F(CliTest, StopSignalsEndARenderWithNoOutput) {
  for (const int signal : {SIGTERM, SIGHUP, SIGINT}) {
    const fs::path out = dir_ / "out.png", err = dir_ / "stderr.txt";
    // Minutes of work: the signal lands during the render, whatever the machine's load.
    const std::string cmd = "exec " + std::string(ILLUM_BINARY_DIR) +
                            "/bin/illum render cornell --width 128 --height 128 --spp 100000 "
                            "-o " +
                            out.string() + " 2>" + err.string() + " </dev/null";
    int status = 0;
    ASSERT_TRUE(signal_and_wait(cmd, std::chrono::milliseconds(1000), signal,
                                std::chrono::seconds(30), &status))
        << "illum did not stop within 30 s of signal " << signal;
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 130) << signal;
    const std::string text = slurp(err);
    const char* name = signal == SIGTERM ? "SIGTERM" : signal == SIGHUP ? "SIGHUP" : "interrupted";
    EXPECT_NE(text.find(name), std::string::npos) << text;
    EXPECT_NE(text.find("nothing was written"), std::string::npos) << text;
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path(), err) << "left behind: " << entry.path();
    fs::remove(err);
  }
}

}  // namespace
