// Progress of long work on stderr, with ETA: a bar redrawn in place on a terminal; when
// stderr is a file or a pipe (CI, batch jobs, mpirun), a plain line every few seconds
// ("render: 37% (12.0s elapsed, ETA 20.4s)") and no carriage returns, so a log of a long
// job shows it moving. Only rank 0 of an MPI job reports (core/work_split.h). Thread-safe:
// workers call advance() concurrently.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace illum {

class Progress {
 public:
  // kAuto: the bar on a terminal, lines otherwise. `enabled` false: silent (counts only).
  enum class Style { kAuto, kBar, kLines };
  Progress(std::string label, int64_t total, bool enabled = true, Style style = Style::kAuto);
  ~Progress();
  void advance(int64_t amount = 1);
  void finish();
  // Work counted so far (also while the bar is disabled) and its share of the total,
  // capped at 1: what the bar shows, observable without a terminal.
  int64_t done() const { return done_.load(); }
  double fraction() const;
  static bool stderr_is_terminal();
  // Formats a duration like "1m05s" / "12.3s"; exposed for tests.
  static std::string format_seconds(double seconds);
  // Seconds between two lines (Style::kLines): 5, or ILLUM_PROGRESS_INTERVAL when set to a
  // positive number (tests use a short one).
  static double line_interval();

 private:
  void draw(int64_t done);
  void print_line(int64_t done);
  std::string label_;
  int64_t total_;
  bool enabled_;
  bool lines_;  // plain lines rather than the bar
  int lines_printed_ = 0;
  std::chrono::steady_clock::duration interval_;
  bool finished_ = false;
  std::atomic<int64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex draw_mutex_;
};

}  // namespace illum
