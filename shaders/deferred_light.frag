#version 450
#include "gbuffer.glsl"
// One light over the G-buffer (light volumes, -p deferred_lighting=volumes; and the
// full-screen pass of stencil shadow volumes, where the stencil masks the shadow): the same
// lighting as the forward path and the compute pass.
layout(location = 0) out vec4 out_color;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(g_depth, pixel, 0).r;
  if (depth >= 1.0) discard;
  Surface s = gbuffer_surface(pixel, depth);
  vec3 v = normalize(views[push.view].camera_pos.xyz - s.p);
  vec3 radiance, l;
  if (!light_contribution(push.light_index, s, v, radiance, l)) discard;
  out_color = vec4(radiance * cube_shadow(push.light_index, s.p, s.ng, gl_FragCoord.xy), 1.0);
}
