// The auto-exposure buffer (set 0, binding 1 of luminance.comp, luminance_reduce.comp and
// tonemap.comp) and the bin of a luminance, as core/auto_exposure.cpp computes them.
layout(std430, set = 0, binding = 1) buffer ExposureData {
  uint bins[kHistogramBins];
  float mean_log2;  // between the percentiles, bin centres
  float exposure;   // kTarget / 2^mean_log2; 1 with no pixel counted
} exposure_data;

int exposure_bin(float l) {
  if (!(l > 0.0)) return -1;
  float position = (log2(l) - kMinLog2) / ((kMaxLog2 - kMinLog2) / float(kHistogramBins));
  if (!(position >= 0.0)) return -1;
  return position >= float(kHistogramBins - 1) ? kHistogramBins - 1 : int(position);
}
