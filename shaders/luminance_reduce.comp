#version 450
// Pass 2: one workgroup sums the tile partials; partials[count] = exp(mean log luminance).
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 1) buffer Partials { float partials[]; };
layout(push_constant) uniform Push { uint count; uint pixels; } push;
shared float sums[256];
void main() {
  uint i = gl_LocalInvocationIndex;
  float v = 0.0;
  for (uint k = i; k < push.count; k += 256) v += partials[k];
  sums[i] = v;
  barrier();
  for (uint s = 128; s > 0; s >>= 1) {
    if (i < s) sums[i] += sums[i + s];
    barrier();
  }
  if (i == 0) partials[push.count] = exp(sums[0] / float(push.pixels));
}
