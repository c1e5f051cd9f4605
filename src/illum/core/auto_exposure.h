// The one auto-exposure rule of illum, for offline images (render, relight) and real-time
// frames (shaders/luminance.comp builds the same histogram from the same constants,
// auto_exposure_constants.h): a log2-luminance histogram, the mean log2 luminance of the
// pixels between two percentiles (bin centres, as engines do), mapped to a target grey.
// Bright outliers above the high percentile (emitters, highlights, caustics) and the dark
// half do not move it; an image scaled by k gets an exposure divided by k (exactly when
// log2 k is a whole number of bins).
#pragma once

#include <array>
#include <cstdint>

#include "illum/core/auto_exposure_constants.h"
#include "illum/core/image.h"

namespace illum {

using ExposureHistogram = std::array<uint32_t, exposure::kHistogramBins>;

// log2 width of a bin: 1/8 stop.
inline constexpr float kExposureBinWidth =
    (exposure::kMaxLog2 - exposure::kMinLog2) / float(exposure::kHistogramBins);

// The bin of a pixel of luminance `l` (Rec. 709 Y of linear RGB), or -1 when it is not
// counted (below the range: black, or darker than 2^kMinLog2; NaN).
int exposure_bin(float l);

// Every pixel's luminance in its bin (alpha ignored).
ExposureHistogram exposure_histogram(const Image& hdr);

struct AutoExposure {
  float exposure = 1.0f;   // kTarget / 2^mean_log2; 1 when no pixel is counted
  float mean_log2 = 0.0f;  // mean log2 luminance between the percentiles (bin centres)
  uint64_t counted = 0;    // pixels in the histogram
};

// The rule applied to a histogram (the GPU's reduction does the same arithmetic).
AutoExposure auto_exposure(const ExposureHistogram& histogram);
AutoExposure auto_exposure(const Image& hdr);

// The exposure an 8-bit image is made with: `exposure` × the auto exposure of `hdr`, or
// `exposure` alone when `fixed` (the --exposure and --fixed-exposure of every command).
float display_exposure(const Image& hdr, float exposure, bool fixed);

}  // namespace illum
