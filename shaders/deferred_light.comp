#version 450
// Deferred lighting in one dispatch: every pixel of the G-buffer loops over the lights (S002
// attenuation, radius and cone culling in light_contribution) and adds the sum to the HDR
// target, which already holds emission + ambient. Replaces per-light full-screen and volume
// draws, whose blending and stencil traffic dominate on fill-limited GPUs.
layout(local_size_x = 8, local_size_y = 8) in;
#include "gbuffer.glsl"
layout(set = 2, binding = 4, rgba16f) uniform image2D hdr_image;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  float depth = texelFetch(g_depth, pixel, 0).r;
  if (depth >= 1.0) return;
  Surface s = gbuffer_surface(pixel, depth);
  vec3 v = normalize(frame.camera_pos.xyz - s.p);
  int first = frame.counts.z >= 0 ? frame.counts.z : 0;
  int last = frame.counts.z >= 0 ? frame.counts.z + 1 : frame.counts.x;
  vec3 sum = vec3(0.0);
  vec2 frag = vec2(pixel) + 0.5;  // gl_FragCoord.xy of the fragment path (same PCF rotation)
  for (int i = first; i < last; ++i) {
    vec3 radiance, l;
    if (!light_contribution(i, s, v, radiance, l)) continue;
    sum += radiance * cube_shadow(i, s.p, s.ng, frag);
  }
  if (all(equal(sum, vec3(0.0)))) return;
  vec4 c = imageLoad(hdr_image, pixel);
  imageStore(hdr_image, pixel, vec4(c.rgb + sum, c.a));
}
