#include "illum/core/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>

#include "illum/core/work_split.h"

namespace illum {

Progress::Progress(std::string label, int64_t total, bool enabled, Style style)
    : label_(std::move(label)),
      total_(std::max<int64_t>(total, 1)),
      // Every rank counts; one line per step from each would repeat rank 0's.
      enabled_(enabled && (!work_split() || work_split()->is_root())),
      lines_(style == Style::kLines || (style == Style::kAuto && !stderr_is_terminal())),
      interval_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(line_interval()))),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

double Progress::line_interval() {
  if (const char* text = std::getenv("ILLUM_PROGRESS_INTERVAL")) {
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (end != text && *end == '\0' && seconds > 0.0 && seconds < 1e6) return seconds;
  }
  return 5.0;
}

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
  if (lines_) {
    if (now - last_draw_ < interval_ || done >= total_) return;  // finish() says the end
    std::unique_lock lock(draw_mutex_, std::try_to_lock);
    if (!lock.owns_lock() || now - last_draw_ < interval_) return;
    last_draw_ = now;
    print_line(done);
    return;
  }
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

void Progress::print_line(int64_t done) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  const double eta = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::fprintf(stderr, "%s: %.0f%% (%s elapsed, ETA %s)\n", label_.c_str(), 100.0 * frac,
               format_seconds(elapsed).c_str(),
               frac > 0.0 ? format_seconds(eta).c_str() : "unknown");
  std::fflush(stderr);
  ++lines_printed_;
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  std::lock_guard lock(draw_mutex_);
  if (lines_) {
    // Work short enough to print no line stays silent; a log that showed it going shows
    // it ending.
    if (lines_printed_ > 0)
      std::fprintf(
          stderr, "%s: %.0f%% in %s\n", label_.c_str(), 100.0 * fraction(),
          format_seconds(
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count())
              .c_str());
    return;
  }
  draw(done_.load());
  std::fputc('\n', stderr);
}

}  // namespace illum
