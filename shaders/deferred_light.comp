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
  vec3 v = normalize(views[push.view].camera_pos.xyz - s.p);
  // gl_FragCoord.xy of the fragment path (same PCF rotation)
  vec3 sum = direct_light(s, v, vec2(pixel) + 0.5);
  if (all(equal(sum, vec3(0.0)))) return;
  vec4 c = imageLoad(hdr_image, pixel);
  imageStore(hdr_image, pixel, vec4(c.rgb + sum, c.a));
}
