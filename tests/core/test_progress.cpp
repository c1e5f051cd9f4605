#include <gtest/gtest.h>

#include "illum/core/progress.h"

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
  Progress progress("test", 10, /*enabled=*/false);
  for (int i = 0; i < 10; ++i) progress.advance();
  progress.finish();
  progress.finish();  // idempotent
}

}  // namespace
}  // namespace illum
