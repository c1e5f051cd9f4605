#version 450
// Pass 2 of auto-exposure: the rule of core/auto_exposure.cpp on the frame's histogram (the
// mean bin centre of the counts between the two percentiles, mapped to kTarget), then the
// histogram cleared for the next frame. One invocation walks the 256 bins: a few
// microseconds, and the same order of operations as the C++.
#include "illum/core/auto_exposure_constants.h"
#include "exposure.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_LocalInvocationIndex;
  if (i == 0u) {
    uint counted = 0u;
    for (int k = 0; k < kHistogramBins; ++k) counted += exposure_data.bins[k];
    if (counted == 0u) {
      exposure_data.mean_log2 = 0.0;
      exposure_data.exposure = 1.0;
    } else {
      float low = kLowPercentile * float(counted), high = kHighPercentile * float(counted);
      float below = 0.0, weight = 0.0, sum = 0.0;
      float width = (kMaxLog2 - kMinLog2) / float(kHistogramBins);
      for (int k = 0; k < kHistogramBins; ++k) {
        float n = float(exposure_data.bins[k]);
        float w = max(0.0, min(below + n, high) - max(below, low));
        below += n;
        weight += w;
        sum += w * (kMinLog2 + (float(k) + 0.5) * width);
      }
      exposure_data.mean_log2 = sum / weight;
      exposure_data.exposure = kTarget / exp2(sum / weight);
    }
  }
  barrier();
  memoryBarrierBuffer();
  exposure_data.bins[i] = 0u;
}
