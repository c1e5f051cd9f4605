// A log-log line plot written as a PNG, with a built-in 5×7 pixel font for the labels (the
// bench has no plotting library to lean on). Used for `illum-bench converge`'s relative
// error against time.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace illum::bench {

struct PlotSeries {
  std::string label;
  std::array<float, 3> rgb{0.0f, 0.0f, 0.0f};  // 0..1
  std::vector<double> x, y;                    // positive values (log axes)
  std::vector<std::string> point_labels;       // drawn beside each point (may be empty)
};

struct LogLogPlot {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  // Optional guide: a line of slope `guide_slope` through the first series' first point.
  bool guide = false;
  double guide_slope = -0.5;
  std::string guide_label;
};

// Throws illum::Error if a value is not positive and finite or the file cannot be written.
void write_loglog_png(const LogLogPlot& plot, const std::string& path, int width = 720,
                      int height = 480);

}  // namespace illum::bench
