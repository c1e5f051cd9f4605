#include "plot_png.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "illum/core/error.h"
#include "illum/core/image.h"

namespace illum::bench {
namespace {

// 5×7 glyphs, one byte per row, bit 4 the leftmost column.
struct Glyph {
  char c;
  uint8_t rows[7];
};
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0, 0, 0, 0, 0, 0x0C, 0x0C}},
    {'-', {0, 0, 0, 0x1F, 0, 0, 0}},
    {'+', {0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'/', {0, 0x01, 0x02, 0x04, 0x08, 0x10, 0}},
    {':', {0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0}},
    {'=', {0, 0, 0x1F, 0, 0x1F, 0, 0}},
    {',', {0, 0, 0, 0, 0x0C, 0x04, 0x08}},
    {'x', {0, 0, 0x11, 0x0A, 0x04, 0x0A, 0x11}},
    {'a', {0, 0, 0x0E, 0x01, 0x0F, 0x11, 0x0F}},
    {'b', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1E}},
    {'c', {0, 0, 0x0E, 0x10, 0x10, 0x11, 0x0E}},
    {'d', {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F}},
    {'e', {0, 0, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
    {'f', {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08}},
    {'g', {0, 0x0F, 0x11, 0x11, 0x0F, 0x01, 0x0E}},
    {'h', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11}},
    {'i', {0x04, 0, 0x0C, 0x04, 0x04, 0x04, 0x0E}},
    {'j', {0x02, 0, 0x06, 0x02, 0x02, 0x12, 0x0C}},
    {'k', {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}},
    {'l', {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'m', {0, 0, 0x1A, 0x15, 0x15, 0x11, 0x11}},
    {'n', {0, 0, 0x16, 0x19, 0x11, 0x11, 0x11}},
    {'o', {0, 0, 0x0E, 0x11, 0x11, 0x11, 0x0E}},
    {'p', {0, 0, 0x1E, 0x11, 0x1E, 0x10, 0x10}},
    {'q', {0, 0, 0x0D, 0x13, 0x0F, 0x01, 0x01}},
    {'r', {0, 0, 0x16, 0x19, 0x10, 0x10, 0x10}},
    {'s', {0, 0, 0x0E, 0x10, 0x0E, 0x01, 0x1E}},
    {'t', {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06}},
    {'u', {0, 0, 0x11, 0x11, 0x11, 0x13, 0x0D}},
    {'v', {0, 0, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'w', {0, 0, 0x11, 0x11, 0x15, 0x15, 0x0A}},
    {'y', {0, 0, 0x11, 0x11, 0x0F, 0x01, 0x0E}},
    {'z', {0, 0, 0x1F, 0x02, 0x04, 0x08, 0x1F}},
};

class Canvas {
 public:
  Canvas(int w, int h) : img_(w, h, 3, 1.0f) {}
  void dot(int x, int y, const Color& c) {
    if (x >= 0 && y >= 0 && x < img_.width() && y < img_.height()) img_.set_rgb(x, y, c);
  }
  void disc(double x, double y, int r, const Color& c) {
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx)
        if (dx * dx + dy * dy <= r * r)
          dot(static_cast<int>(std::lround(x)) + dx, static_cast<int>(std::lround(y)) + dy, c);
  }
  void line(double x0, double y0, double x1, double y1, const Color& c, int thick = 1) {
    const int n = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      const double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
      if (thick <= 1)
        dot(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)), c);
      else
        disc(x, y, thick / 2, c);
    }
  }
  // Text with its top-left corner at (x, y); `vertical` writes bottom to top.
  void text(int x, int y, const std::string& s, const Color& c, int scale = 1,
            bool vertical = false) {
    for (size_t k = 0; k < s.size(); ++k) {
      const Glyph* g = nullptr;
      for (const Glyph& f : kFont)
        if (f.c == s[k]) g = &f;
      for (int row = 0; row < 7 && g; ++row)
        for (int col = 0; col < 5; ++col) {
          if (!(g->rows[row] & (0x10 >> col))) continue;
          for (int sy = 0; sy < scale; ++sy)
            for (int sx = 0; sx < scale; ++sx) {
              const int gx = static_cast<int>(k) * 6 * scale + col * scale + sx,
                        gy = row * scale + sy;
              if (vertical)
                dot(x + gy, y - gx, c);
              else
                dot(x + gx, y + gy, c);
            }
        }
    }
  }
  const Image& image() const { return img_; }

 private:
  Image img_;
};

std::string tick_label(double v) {
  if (v >= 1e-2 && v < 1e4) {
    std::string s = fmt::format("{:g}", v);
    return s;
  }
  return fmt::format("1e{}", static_cast<int>(std::lround(std::log10(v))));
}

}  // namespace

void write_loglog_png(const LogLogPlot& plot, const std::string& path, int width, int height) {
  double x_lo = 1e300, x_hi = 0.0, y_lo = 1e300, y_hi = 0.0;
  for (const PlotSeries& s : plot.series)
    for (size_t i = 0; i < s.x.size(); ++i) {
      const double x = s.x[i], y = s.y[i];
      if (!(x > 0.0) || !(y > 0.0) || !std::isfinite(x) || !std::isfinite(y))
        throw Error(fmt::format("{}: plot value ({}, {}) is not positive and finite", path, x, y));
      x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
    }
  if (x_hi == 0.0) throw Error(fmt::format("{}: nothing to plot", path));
  // Whole decades around the data.
  const double lx0 = std::floor(std::log10(x_lo)), lx1 = std::ceil(std::log10(x_hi) + 1e-9);
  const double ly0 = std::floor(std::log10(y_lo)), ly1 = std::ceil(std::log10(y_hi) + 1e-9);
  const int left = 80, right = 20, top = 40, bottom = 60;
  const double pw = width - left - right, ph = height - top - bottom;
  auto px = [&](double x) { return left + (std::log10(x) - lx0) / (lx1 - lx0) * pw; };
  auto py = [&](double y) { return top + (ly1 - std::log10(y)) / (ly1 - ly0) * ph; };

  Canvas c(width, height);
  const Color ink(0.0f), grid(0.85f);
  for (double d = lx0; d <= lx1 + 1e-9; d += 1.0) {
    for (int m = 1; m < 10 && d + std::log10(m) <= lx1 + 1e-9; ++m) {
      const double x = px(std::pow(10.0, d) * m);
      c.line(x, top, x, top + ph, m == 1 ? Color(0.7f) : grid);
    }
    const std::string t = tick_label(std::pow(10.0, d));
    c.text(static_cast<int>(px(std::pow(10.0, d))) - 3 * static_cast<int>(t.size()),
           top + static_cast<int>(ph) + 8, t, ink);
  }
  for (double d = ly0; d <= ly1 + 1e-9; d += 1.0) {
    for (int m = 1; m < 10 && d + std::log10(m) <= ly1 + 1e-9; ++m) {
      const double y = py(std::pow(10.0, d) * m);
      c.line(left, y, left + pw, y, m == 1 ? Color(0.7f) : grid);
    }
    const std::string t = tick_label(std::pow(10.0, d));
    c.text(left - 8 - 6 * static_cast<int>(t.size()), static_cast<int>(py(std::pow(10.0, d))) - 3,
           t, ink);
  }
  c.line(left, top, left, top + ph, ink);
  c.line(left, top + ph, left + pw, top + ph, ink);
  c.text(left, 12, plot.title, ink, 2);
  c.text(left + static_cast<int>(pw / 2) - 6 * static_cast<int>(plot.x_label.size()), height - 24,
         plot.x_label, ink, 2);
  c.text(14, top + static_cast<int>(ph / 2) + 6 * static_cast<int>(plot.y_label.size()),
         plot.y_label, ink, 2, /*vertical=*/true);

  if (plot.guide && !plot.series.empty() && !plot.series[0].x.empty()) {
    const double x0 = plot.series[0].x[0], y0 = plot.series[0].y[0];
    const double xa = std::pow(10.0, lx0), xb = std::pow(10.0, lx1);
    auto gy = [&](double x) { return y0 * std::pow(x / x0, plot.guide_slope); };
    // Clipped to the plot's y range: x where the guide leaves [10^ly0, 10^ly1].
    const double ya = std::pow(10.0, ly1), yb = std::pow(10.0, ly0);
    const double x_top = x0 * std::pow(ya / y0, 1.0 / plot.guide_slope),
                 x_bottom = x0 * std::pow(yb / y0, 1.0 / plot.guide_slope);
    const double c0 = std::max(xa, std::min(x_top, x_bottom)),
                 c1 = std::min(xb, std::max(x_top, x_bottom));
    if (c0 < c1) c.line(px(c0), py(gy(c0)), px(c1), py(gy(c1)), Color(0.55f));
    if (!plot.guide_label.empty())
      c.text(static_cast<int>(px(xb)) - 6 * static_cast<int>(plot.guide_label.size()) - 4,
             static_cast<int>(py(gy(xb))) - 12, plot.guide_label, Color(0.45f));
  }
  int legend_y = top + 8;
  for (const PlotSeries& s : plot.series) {
    const Color col(s.rgb[0], s.rgb[1], s.rgb[2]);
    for (size_t i = 0; i + 1 < s.x.size(); ++i)
      c.line(px(s.x[i]), py(s.y[i]), px(s.x[i + 1]), py(s.y[i + 1]), col, 2);
    for (size_t i = 0; i < s.x.size(); ++i) {
      c.disc(px(s.x[i]), py(s.y[i]), 4, col);
      if (i < s.point_labels.size())
        c.text(static_cast<int>(px(s.x[i])) + 7, static_cast<int>(py(s.y[i])) + 4,
               s.point_labels[i], col);
    }
    const int lx = left + static_cast<int>(pw) - 150;
    c.line(lx, legend_y + 6, lx + 24, legend_y + 6, col, 3);
    c.text(lx + 32, legend_y, s.label, col, 2);
    legend_y += 22;
  }
  ImageWriteOptions o;
  o.srgb = false;  // the canvas holds display values already
  write_image(path, c.image(), o);
}

}  // namespace illum::bench
