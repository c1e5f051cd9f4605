// Signals: SIGINT, SIGTERM and SIGHUP each set the interrupt flag once; a second signal ends
// the process at once, removing the registered staging files and folders first. Each case
// runs in a forked child, which installs the handler and raises the signals itself.
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "illum/core/interrupt.h"

namespace illum {
namespace {

namespace fs = std::filesystem;

// Runs `child` in a fork; returns its exit code (128 + signal if a signal killed it).
template <typename F>
int in_child(F child) {
  const pid_t pid = fork();
  if (pid == 0) {
    child();
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

fs::path scratch(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("illum-interrupt-" + std::to_string(getpid()) + "-" + name);
  fs::remove_all(p);
  return p;
}

TEST(Interrupt, EachStopSignalSetsTheFlagOnce) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const int code = in_child([signal] {
      install_interrupt_handler();
      if (interrupt_requested()) _exit(10);
      raise(signal);
      if (!interrupt_requested()) _exit(11);
      if (interrupt_signal() != signal) _exit(12);
      _exit(0);  // still running: the first signal does not end the process
    });
    EXPECT_EQ(code, 0) << "signal " << signal;
  }
}

TEST(Interrupt, SecondSignalRemovesStagingPathsAndQuits) {
  const fs::path file = scratch("file.tmp"), folder = scratch("folder"), kept = scratch("kept.txt");
  for (const int second : {SIGINT, SIGTERM, SIGHUP}) {
    fs::create_directories(folder);
    std::ofstream(folder / "layer0.exr") << "partial";
    std::ofstream(folder / ".preview.png.1-0.tmp") << "partial";
    std::ofstream(file) << "partial";
    std::ofstream(kept) << "a published output";
    const int code = in_child([&] {
      install_interrupt_handler();
      const StagingPath a(file.string()), b(folder.string());
      {
        const StagingPath done(kept.string());  // published, then no longer staged
      }
      raise(SIGINT);
      raise(second);
      _exit(0);  // not reached: the second signal quits
    });
    EXPECT_EQ(code, 130) << "signal " << second;
    EXPECT_FALSE(fs::exists(file)) << "signal " << second;
    EXPECT_FALSE(fs::exists(folder)) << "signal " << second;
    EXPECT_TRUE(fs::exists(kept)) << "an unregistered file is never removed";
  }
  fs::remove(kept);
}

}  // namespace
}  // namespace illum
