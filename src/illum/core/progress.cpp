#include "illum/core/progress.h"

#include <unistd.h>

#include <cstdio>

#include <fmt/format.h>

namespace illum {

Progress::Progress(std::string label, int64_t total, bool enabled)
    : label_(std::move(label)),
      total_(std::max<int64_t>(total, 1)),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  finish();
}

bool Progress::stderr_is_terminal() {
  return isatty(STDERR_FILENO) == 1;
}

std::string Progress::format_seconds(double s) {
  // Below 59.95 s the one-decimal form cannot round up to "60.0s".
  if (s < 59.95) return fmt::format("{:.1f}s", s);
  const int total = static_cast<int>(s + 0.5);
  if (total < 3600) return fmt::format("{}m{:02d}s", total / 60, total % 60);
  return fmt::format("{}h{:02d}m", total / 3600, (total % 3600) / 60);
}

void Progress::advance(int64_t amount) {
  const int64_t done = done_.fetch_add(amount) + amount;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  // Redraw at most ten times a second; try_lock keeps workers from queueing on the bar.
  if (now - last_draw_ < std::chrono::milliseconds(100) && done < total_) return;
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  last_draw_ = now;
  draw(done);
}

double Progress::fraction() const {
  return std::min(1.0, static_cast<double>(done_.load()) / static_cast<double>(total_));
}

void Progress::draw(int64_t done) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  const int width = 30;
  const int filled = static_cast<int>(frac * width);
  const double eta = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r%s [%s] %5.1f%% %s elapsed, ETA %s   ", label_.c_str(), bar.c_str(),
               100.0 * frac, format_seconds(elapsed).c_str(), format_seconds(eta).c_str());
  std::fflush(stderr);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  std::lock_guard lock(draw_mutex_);
  draw(done_.load());
  std::fputc('\n', stderr);
}

}  // namespace illum
