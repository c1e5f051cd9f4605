#version 450
// Pass 1 of auto-exposure: every pixel's log2 luminance in the histogram of
// core/auto_exposure.h (same bins, same range, same constants), counted per workgroup in
// shared memory, then added to the frame's histogram.
#include "illum/core/auto_exposure_constants.h"
#include "exposure.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D hdr;
shared uint local_bins[kHistogramBins];
void main() {
  uint i = gl_LocalInvocationIndex;
  // 256 invocations, 256 bins: each clears and later flushes one.
  local_bins[i] = 0u;
  barrier();
  ivec2 size = textureSize(hdr, 0);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x < size.x && p.y < size.y) {
    vec3 c = texelFetch(hdr, p, 0).rgb;
    int bin = exposure_bin(kLumaR * c.r + kLumaG * c.g + kLumaB * c.b);
    if (bin >= 0) atomicAdd(local_bins[bin], 1u);
  }
  barrier();
  if (local_bins[i] != 0u) atomicAdd(exposure_data.bins[i], local_bins[i]);
}
