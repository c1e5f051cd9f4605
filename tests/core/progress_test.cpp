#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include <algorithm>
#include <string>

#include "illum/core/progress.h"
#include "illum/core/work_split.h"

namespace illum {
namespace {

TEST(Progress, FormatSeconds) {
  EXPECT_EQ(Progress::format_seconds(0.0), "0.0s");
  EXPECT_EQ(Progress::format_seconds(12.34), "12.3s");
  EXPECT_EQ(Progress::format_seconds(59.9), "59.9s");
  // Values that would print as "60.0s" switch to minutes.
  EXPECT_EQ(Progress::format_seconds(59.97), "1m00s");
  EXPECT_EQ(Progress::format_seconds(65.0), "1m05s");
  EXPECT_EQ(Progress::format_seconds(3599.4), "59m59s");
  EXPECT_EQ(Progress::format_seconds(3599.6), "1h00m");
  EXPECT_EQ(Progress::format_seconds(3725.0), "1h02m");
  EXPECT_EQ(Progress::format_seconds(90061.0), "25h01m");
}

TEST(Progress, DisabledBarCountsSilently) {
  // A disabled bar (stderr not a terminal: CI, pipes) still counts, and writes nothing.
  testing::internal::CaptureStderr();
  {
    Progress progress("test", 10, /*enabled=*/false);
    EXPECT_EQ(progress.done(), 0);
    EXPECT_EQ(progress.fraction(), 0.0);
    for (int i = 0; i < 4; ++i) progress.advance();
    EXPECT_EQ(progress.done(), 4);
    EXPECT_DOUBLE_EQ(progress.fraction(), 0.4);
    progress.advance(8);  // past the total: counted, the fraction capped
    EXPECT_EQ(progress.done(), 12);
    EXPECT_EQ(progress.fraction(), 1.0);
    progress.finish();
    progress.finish();  // idempotent
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Progress, EnabledBarDrawsOnceFinished) {
  // The control for the check above (the capture sees what the bar writes): the same calls
  // on an enabled bar draw it, and finish() ends it with exactly one newline.
  testing::internal::CaptureStderr();
  {
    Progress progress("test", 10, /*enabled=*/true, Progress::Style::kBar);
    for (int i = 0; i < 10; ++i) progress.advance();
    EXPECT_EQ(progress.done(), 10);
    progress.finish();
    progress.finish();
  }
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("test ["), std::string::npos) << out;
  EXPECT_NE(out.find("100.0%"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_EQ(out.back(), '\n');
}

// Where stderr is a file (the capture here, a batch job's log): whole lines at the interval,
// no carriage return, and an end line once any was printed; quick work prints nothing.
TEST(Progress, LinesWhenStderrIsNotATerminal) {
  ::setenv("ILLUM_PROGRESS_INTERVAL", "0.05", 1);
  testing::internal::CaptureStderr();
  {
    Progress progress("bake", 4);  // kAuto: the capture is not a terminal
    progress.advance();
    std::this_thread::sleep_for(std::chrono::milliseconds(80));
    progress.advance();  // 50%, past the interval: a line
    progress.advance();  // 75%, within it: none
    progress.advance();
  }
  const std::string out = testing::internal::GetCapturedStderr();
  testing::internal::CaptureStderr();
  {
    Progress quick("quick", 4);
    for (int i = 0; i < 4; ++i) quick.advance();
  }
  const std::string quiet = testing::internal::GetCapturedStderr();
  ::unsetenv("ILLUM_PROGRESS_INTERVAL");
  EXPECT_EQ(out.find('\r'), std::string::npos) << out;
  EXPECT_EQ(out.rfind("bake: 50% (", 0), 0u) << out;
  EXPECT_EQ(out.find("75%"), std::string::npos) << out;
  EXPECT_NE(out.find("\nbake: 100% in "), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 2) << out;
  EXPECT_EQ(quiet, "");
}

// Under mpirun every rank counts its share, and only rank 0 reports: another rank's lines
// would repeat its own.
TEST(Progress, OnlyRankZeroReports) {
  struct Rank : WorkSplit {
    int id = 0;
    int ranks() const override { return 2; }
    int rank() const override { return id; }
    int threads_per_rank() const override { return 1; }
    void run(int64_t, size_t, int, const UnitWork&, const UnitKeep&) override {}
  };
  Rank rank;
  std::string said[2];
  for (int id : {0, 1}) {
    rank.id = id;
    const ScopedWorkSplit installed(&rank);
    testing::internal::CaptureStderr();
    {
      Progress progress("bake", 4, /*enabled=*/true, Progress::Style::kBar);
      for (int i = 0; i < 4; ++i) progress.advance();
      EXPECT_EQ(progress.done(), 4);
    }
    said[id] = testing::internal::GetCapturedStderr();
  }
  EXPECT_NE(said[0].find("100.0%"), std::string::npos) << said[0];
  EXPECT_EQ(said[1], "");
}

}  // namespace
}  // namespace illum
