#version 450
// Bloom, step 1: bright pass at half resolution — what exceeds the threshold (bilinear
// fetch at the centre of each 2×2 block averages it).
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D dst;
layout(push_constant) uniform Push { vec2 direction; float threshold; int radius; } push;
void main() {
  ivec2 size = imageSize(dst);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  vec3 c = textureLod(src, (vec2(p) + 0.5) / vec2(size), 0.0).rgb;
  imageStore(dst, p, vec4(max(c - push.threshold, 0.0), 1.0));
}
