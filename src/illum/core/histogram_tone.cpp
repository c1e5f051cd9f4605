#include "illum/core/histogram_tone.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include "illum/core/color.h"

#include "illum/core/error.h"

namespace illum {

HistogramToneCurve::HistogramToneCurve(const std::vector<float>& luminances,
                                       const HistogramToneOptions& options)
    : options_(options) {
  if (!(options.display_min > 0.0f && options.display_max > options.display_min &&
        std::isfinite(options.display_max)))
    throw Error(
        fmt::format("histogram tone: display range [{}, {}] must be positive and increasing",
                    options.display_min, options.display_max));
  if (options.bins < 2 || options.bins > 100000)
    throw Error(fmt::format("histogram tone: {} bins (2 to 100000)", options.bins));
  if (!(options.tolerance > 0.0f && options.tolerance < 1.0f))
    throw Error(fmt::format("histogram tone: tolerance {} outside (0, 1)", options.tolerance));
  float lo = INFINITY, hi = 0.0f;
  for (float l : luminances)
    if (l > 0.0f && std::isfinite(l)) {
      lo = std::min(lo, l);
      hi = std::max(hi, l);
    }
  if (!(hi > 0.0f)) return;  // nothing lit: linear, and every value maps to black
  scale_ = options.display_max / hi;
  log_min_ = std::log(lo);
  log_max_ = std::log(hi);
  const double display_range = std::log(double(options.display_max) / options.display_min);
  if (log_max_ - log_min_ <= display_range) return;  // fits the display: linear

  const int n = options.bins;
  const double width = (log_max_ - log_min_) / n;
  std::vector<double> f(static_cast<size_t>(n), 0.0);
  for (float l : luminances)
    if (l > 0.0f && std::isfinite(l)) {
      const int b = std::min(n - 1, static_cast<int>((std::log(l) - log_min_) / width));
      f[static_cast<size_t>(b)] += 1.0;
    }
  double total = 0.0;
  for (double v : f) total += v;
  const double original = total;
  // The linear ceiling: a bin may hold at most total · width / display_range samples, else
  // its slope d log Ld / d log Lw = display_range · f / (total · width) exceeds 1. Trimming
  // lowers the total and so the ceiling: repeat until nothing more is cut. (LRP97 stops once
  // less than `tolerance` of the samples is cut in a round, which leaves capped bins up to
  // 1 / (1 − cut / total) steeper than linear — 14 % in a test here; the loop converges
  // geometrically, so it runs to the end instead.)
  for (int iteration = 0; iteration < 10000; ++iteration) {
    const double ceiling = total * width / display_range;
    double trimmed = 0.0;
    for (double& v : f)
      if (v > ceiling) {
        trimmed += v - ceiling;
        v = ceiling;
      }
    total -= trimmed;
    if (trimmed <= 1e-9 * original) break;
  }
  // LRP97: if almost everything was trimmed, the histogram is flat enough for a linear
  // mapping (the range only just exceeds the display's).
  if (total <= options.tolerance * original) return;
  linear_ = false;
  cumulative_.assign(static_cast<size_t>(n) + 1, 0.0);
  for (int b = 0; b < n; ++b)
    cumulative_[static_cast<size_t>(b) + 1] =
        cumulative_[static_cast<size_t>(b)] + f[static_cast<size_t>(b)] / total;
}

float HistogramToneCurve::display(float world) const {
  if (!(world > 0.0f) || !std::isfinite(world)) return options_.display_min;
  if (linear_) return std::clamp(world * scale_, options_.display_min, options_.display_max);
  const int n = static_cast<int>(cumulative_.size()) - 1;
  const double x =
      std::clamp(double(std::log(world) - log_min_) / double(log_max_ - log_min_), 0.0, 1.0) * n;
  const int b = std::min(n - 1, static_cast<int>(x));
  const double p =
      cumulative_[static_cast<size_t>(b)] +
      (x - b) * (cumulative_[static_cast<size_t>(b) + 1] - cumulative_[static_cast<size_t>(b)]);
  const double lmin = std::log(double(options_.display_min)),
               lmax = std::log(double(options_.display_max));
  return static_cast<float>(std::exp(lmin + (lmax - lmin) * p));
}

Image histogram_tone_mapped(const Image& hdr, const HistogramToneOptions& options) {
  ILLUM_CHECK(hdr.channels() >= 3, "histogram tone: a colour image is needed");
  std::vector<float> lum;
  lum.reserve(static_cast<size_t>(hdr.width()) * hdr.height());
  for (int y = 0; y < hdr.height(); ++y)
    for (int x = 0; x < hdr.width(); ++x) lum.push_back(luminance(hdr.rgb(x, y)));
  const HistogramToneCurve curve(lum, options);
  Image out = hdr;
  for (int y = 0; y < hdr.height(); ++y)
    for (int x = 0; x < hdr.width(); ++x) {
      const Color c = hdr.rgb(x, y);
      const float l = luminance(c);
      const float k =
          l > 0.0f && std::isfinite(l) ? curve.display(l) / l / options.display_max : 0.0f;
      // A saturated colour whose brightest channel would pass 1 is scaled down as a whole:
      // the hue is kept, not clipped per channel.
      Color mapped = glm::max(c * k, Color(0.0f));
      const float peak = std::max({mapped.r, mapped.g, mapped.b});
      if (peak > 1.0f) mapped /= peak;
      float* p = out.pixel(x, y);
      for (int ch = 0; ch < 3; ++ch) p[ch] = mapped[ch];  // alpha, if any, untouched
    }
  return out;
}

}  // namespace illum
