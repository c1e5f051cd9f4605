// A terminal progress bar with rate and ETA. Silent when stderr is not a terminal (CI,
// pipes), so logs stay clean. Thread-safe: workers call advance() concurrently.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace illum {

class Progress {
 public:
  Progress(std::string label, int64_t total, bool enabled = stderr_is_terminal());
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

 private:
  void draw(int64_t done);
  std::string label_;
  int64_t total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<int64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex draw_mutex_;
};

}  // namespace illum
