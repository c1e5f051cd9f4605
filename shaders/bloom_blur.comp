#version 450
// Bloom, steps 2–3: separable Gaussian (σ = radius / 3) along push.direction.
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D dst;
layout(push_constant) uniform Push { vec2 direction; float threshold; int radius; } push;
void main() {
  ivec2 size = imageSize(dst);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  float sigma = max(float(push.radius) / 3.0, 0.5);
  vec3 sum = vec3(0.0);
  float weights = 0.0;
  for (int i = -push.radius; i <= push.radius; ++i) {
    float w = exp(-float(i * i) / (2.0 * sigma * sigma));
    ivec2 q = clamp(p + ivec2(push.direction * float(i)), ivec2(0), size - 1);
    sum += w * texelFetch(src, q, 0).rgb;
    weights += w;
  }
  imageStore(dst, p, vec4(sum / weights, 1.0));
}
