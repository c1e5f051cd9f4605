#include "converge_stats.h"

#include <cmath>
#include <numbers>

#include "illum/core/error.h"
#include "illum/core/image.h"

namespace illum::bench {
namespace {

void check_same_size(const Image& a, const Image& b, const char* what) {
  if (a.empty() || b.empty()) throw Error(fmt::format("converge: {}: empty image", what));
  if (a.width() != b.width() || a.height() != b.height())
    throw Error(fmt::format("converge: {}: {}x{} against {}x{}", what, a.width(), a.height(),
                            b.width(), b.height()));
}

}  // namespace

double image_mean(const Image& image) {
  if (image.empty()) throw Error("converge: mean of an empty image");
  double sum = 0.0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Color c = image.rgb(x, y);
      sum += static_cast<double>(c.r) + c.g + c.b;
    }
  return sum / (3.0 * static_cast<double>(image.pixel_count()));
}

RelativeVariance relative_variance(const Image& a, const Image& b, const Image& reference,
                                   double floor_fraction) {
  check_same_size(a, b, "the two renders");
  check_same_size(a, reference, "render against reference");
  const double mean_ref = image_mean(reference);
  if (!(mean_ref > 0.0) || !std::isfinite(mean_ref))
    throw Error(fmt::format("converge: reference mean {} (black or not finite)", mean_ref));
  RelativeVariance r;
  r.epsilon = (floor_fraction * mean_ref) * (floor_fraction * mean_ref);
  double sum = 0.0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const Color ca = a.rgb(x, y), cb = b.rgb(x, y), cr = reference.rgb(x, y);
      for (int c = 0; c < 3; ++c) {
        const double d = static_cast<double>(ca[c]) - cb[c];
        const double ref = cr[c];
        sum += 0.5 * d * d / (ref * ref + r.epsilon);
      }
    }
  r.terms = 3 * a.pixel_count();
  r.value = sum / static_cast<double>(r.terms);
  if (!std::isfinite(r.value))
    throw Error("converge: a render holds a non-finite value (variance not finite)");
  return r;
}

double efficiency(double relative_variance, double seconds) {
  if (!(relative_variance > 0.0) || !std::isfinite(relative_variance) || !(seconds > 0.0) ||
      !std::isfinite(seconds))
    throw Error(fmt::format("converge: efficiency of variance {} over {} s is undefined",
                            relative_variance, seconds));
  return 1.0 / (relative_variance * seconds);
}

double reference_relative_variance(double relative_variance, int spp, int reference_spp) {
  if (spp < 1 || reference_spp < 1)
    throw Error(
        fmt::format("converge: sample counts {} and {} must be positive", spp, reference_spp));
  return relative_variance * static_cast<double>(spp) / static_cast<double>(reference_spp);
}

double cycles_point_power(double intensity_w_per_sr) {
  return 4.0 * std::numbers::pi * intensity_w_per_sr;
}

double cycles_ies_spot_power(double intensity_w_per_sr) {
  return cycles_point_power(intensity_w_per_sr) / kCyclesIesScale;
}

int cycles_max_bounces(int illum_max_bounces) {
  if (illum_max_bounces < 1)
    throw Error(fmt::format(
        "converge: max_bounces {} has no Cycles equivalent (Cycles' 0 already adds direct light)",
        illum_max_bounces));
  return illum_max_bounces - 1;
}

}  // namespace illum::bench
