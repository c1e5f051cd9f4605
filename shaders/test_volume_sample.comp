#version 450
// Test kernel (tests/realtime/frame_graph_gpu_test): trilinear lookups of a 3-D image at
// given normalized coordinates.
layout(local_size_x = 64) in;
layout(binding = 0) uniform sampler3D volume;
layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 2) writeonly buffer Values { float values[]; };
layout(push_constant) uniform Push { uint count; } push;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < push.count) values[i] = textureLod(volume, points[i].xyz, 0.0).r;
}
