#version 450
// Test kernel: combine_ambient_occlusion over pairs (tests/realtime/ssao_test).
layout(local_size_x = 64) in;
#include "ambient_occlusion.glsl"
layout(std430, binding = 0) buffer Pairs { vec2 pairs[]; };
layout(std430, binding = 1) buffer Out { float combined[]; };
layout(push_constant) uniform Push { uint count; } push;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < push.count) combined[i] = combine_ambient_occlusion(pairs[i].x, pairs[i].y);
}
