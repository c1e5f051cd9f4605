#include "illum/core/auto_exposure.h"

#include <algorithm>
#include <cmath>

namespace illum {

int exposure_bin(float l) {
  if (!(l > 0.0f)) return -1;
  const float position = (std::log2(l) - exposure::kMinLog2) / kExposureBinWidth;
  if (!(position >= 0.0f)) return -1;
  // Floats compare before the cast: a huge luminance must not overflow the int.
  return position >= float(exposure::kHistogramBins - 1) ? exposure::kHistogramBins - 1
                                                         : static_cast<int>(position);
}

ExposureHistogram exposure_histogram(const Image& hdr) {
  ExposureHistogram h{};
  for (int y = 0; y < hdr.height(); ++y)
    for (int x = 0; x < hdr.width(); ++x) {
      const Color c = hdr.rgb(x, y);
      const float l = exposure::kLumaR * c.r + exposure::kLumaG * c.g + exposure::kLumaB * c.b;
      const int bin = exposure_bin(l);
      if (bin >= 0) ++h[size_t(bin)];
    }
  return h;
}

AutoExposure auto_exposure(const ExposureHistogram& histogram) {
  AutoExposure out;
  for (uint32_t n : histogram) out.counted += n;
  if (out.counted == 0) return out;
  // Each bin contributes the part of its count that lies between the two percentiles.
  const double low = exposure::kLowPercentile * double(out.counted);
  const double high = exposure::kHighPercentile * double(out.counted);
  double below = 0.0, weight = 0.0, sum = 0.0;
  for (int i = 0; i < exposure::kHistogramBins; ++i) {
    const double n = histogram[size_t(i)];
    const double w = std::max(0.0, std::min(below + n, high) - std::max(below, low));
    below += n;
    const double centre = exposure::kMinLog2 + (i + 0.5) * double(kExposureBinWidth);
    weight += w;
    sum += w * centre;
  }
  out.mean_log2 = float(sum / weight);
  out.exposure = float(exposure::kTarget / std::exp2(sum / weight));
  return out;
}

AutoExposure auto_exposure(const Image& hdr) {
  return auto_exposure(exposure_histogram(hdr));
}

float display_exposure(const Image& hdr, float exposure, bool fixed) {
  return fixed ? exposure : exposure * auto_exposure(hdr).exposure;
}

}  // namespace illum
