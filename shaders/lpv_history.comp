#version 450
// Temporal amortisation of the LPV (techniques/lpv.cpp, docs/realtime-lpv.md): a cascade
// rebuilt this frame moves its history towards the new accumulation by lpv.blend.x, so that
// an update fades in instead of popping; it restarts from the accumulation where its box moved
// (the old cells hold other places) or it was never built. Other cascades keep their history.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "lpv_common.glsl"

layout(std430, set = 0, binding = 2) buffer History { float history[]; };
layout(std430, set = 0, binding = 4) readonly buffer Accumulation { float acc[]; };

void main() {
  int n = lpv.info.x;
  ivec3 x = ivec3(gl_GlobalInvocationID);
  int q = x.z / n;
  x.z -= q * n;
  if (any(greaterThanEqual(x, ivec3(n))) || q >= lpv.cascades.x || !lpv_rebuilt(q)) return;
  bool restart = (lpv.cascades.z & (1 << q)) != 0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 4; ++k) {
      int i = lpv_index(q, x, c, k);
      history[i] = restart ? acc[i] : mix(history[i], acc[i], lpv.blend.x);
    }
}
