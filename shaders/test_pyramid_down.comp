#version 450
// Test kernel (tests/realtime/frame_graph_gpu_test): level m of a pyramid, the mean of the
// 2×2 texels of level m − 1, read through that level's own view while it is sampled and
// level m is a storage image.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D above;
layout(binding = 1, r32f) uniform writeonly image2D level;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(level)))) return;
  ivec2 q = 2 * p;
  float sum = texelFetch(above, q, 0).r + texelFetch(above, q + ivec2(1, 0), 0).r +
              texelFetch(above, q + ivec2(0, 1), 0).r + texelFetch(above, q + ivec2(1, 1), 0).r;
  imageStore(level, p, vec4(0.25 * sum));
}
