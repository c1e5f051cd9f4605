#version 450
// Test kernel (tests/realtime/frame_graph_gpu_test): level 0 of a pyramid, a fixed pattern.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r32f) uniform writeonly image2D level;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(level)))) return;
  imageStore(level, p, vec4(float((p.x * 7 + p.y * 13) % 17)));
}
