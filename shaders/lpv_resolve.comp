#version 450
// Copies the LPV's accumulated light (float buffer, techniques/lpv.cpp) into "lpv.accum", the
// image the lighting input samples trilinearly: an atlas of three parts along x (R, G, B),
// each texel (c0, c.x, c.y, c.z) of lpv_common.glsl.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "lpv_common.glsl"

layout(std430, set = 0, binding = 4) readonly buffer Accumulation { float acc[]; };
layout(set = 0, binding = 9, rgba16f) uniform writeonly image3D accum;

void main() {
  int n = lpv.info.x;
  ivec3 x = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(x, ivec3(n)))) return;
  for (int c = 0; c < 3; ++c) {
    int i = lpv_index(x, c, 0);
    imageStore(accum, ivec3(x.x + c * n, x.y, x.z),
               vec4(acc[i], acc[i + 1], acc[i + 2], acc[i + 3]));
  }
}
