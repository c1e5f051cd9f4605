// Histogram adjustment tone reproduction (Larson, Rushmeier & Piatko 1997, LRP97), the
// operator S002 §3.3.5 applies to light-maps, for 8-bit exports only (HDR data stays
// linear). World luminances are ranked by a histogram of their logarithms and spread over
// the display's range (histogram equalization), with LRP97's linear ceiling: no part of the
// curve has more contrast than a linear mapping (d log Ld / d log Lw ≤ 1), so sparsely
// populated ranges are not stretched. Without LRP97's visual model (glare, acuity, colour
// sensitivity): light-maps are textures, not views.
#pragma once

#include <vector>

#include "illum/core/image.h"

namespace illum {

struct HistogramToneOptions {
  float display_min = 1.0f;    // cd/m²: an 8-bit display's black (1:100 contrast)
  float display_max = 100.0f;  // cd/m²
  int bins = 100;              // LRP97: 100 bins over the world's log range
  float tolerance = 0.025f;    // LRP97: stop trimming when < 2.5 % of the samples are cut
};

class HistogramToneCurve {
 public:
  // From world luminances (each sample weighs the same; non-positive and non-finite ones
  // are ignored). Throws Error for options outside their domain.
  explicit HistogramToneCurve(const std::vector<float>& luminances,
                              const HistogramToneOptions& options = {});

  // Display luminance of world luminance `world`, in [display_min, display_max].
  float display(float world) const;
  // Whether the world's dynamic range fits the display's: then the curve is linear
  // (display = world × display_max / world_max), as LRP97 prescribes.
  bool linear() const { return linear_; }

 private:
  HistogramToneOptions options_;
  bool linear_ = true;
  float log_min_ = 0.0f, log_max_ = 0.0f, scale_ = 1.0f;
  std::vector<double> cumulative_;  // bins + 1 values, 0 … 1
};

// An 8-bit-ready copy of `hdr`: every pixel's colour scaled by display(Lw) / Lw /
// display_max (linear display values in [0, 1]; sRGB encoding happens when written; a
// colour whose brightest channel would pass 1 is scaled down whole, keeping its hue), the
// curve built from the image's own non-zero luminances (alpha kept).
Image histogram_tone_mapped(const Image& hdr, const HistogramToneOptions& options = {});

}  // namespace illum
