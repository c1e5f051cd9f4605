#version 450
// Pass 1 of the log-average luminance: each 16×16 tile sums log(δ + L) into partials[tile]
// (δ = 1e-4: realtime::kLogAverageDelta, which the tests use to recompute L_avg on the CPU).
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D hdr;
layout(std430, set = 0, binding = 1) buffer Partials { float partials[]; };
shared float sums[256];
void main() {
  ivec2 size = textureSize(hdr, 0);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  float v = 0.0;
  if (p.x < size.x && p.y < size.y) {
    vec3 c = texelFetch(hdr, p, 0).rgb;
    v = log(1e-4 + max(dot(c, vec3(0.2126, 0.7152, 0.0722)), 0.0));
  }
  uint i = gl_LocalInvocationIndex;
  sums[i] = v;
  barrier();
  for (uint s = 128; s > 0; s >>= 1) {
    if (i < s) sums[i] += sums[i + s];
    barrier();
  }
  if (i == 0) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = sums[0];
}
