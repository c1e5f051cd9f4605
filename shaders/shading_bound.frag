#version 450
#include "gbuffer.glsl"
// The shading bound of the forward pass (realtime/measure/shading_bound.h, illum-bench raster):
// each covered pixel once, forward.frag's lighting (direct_light: the same lights, shadow maps and
// BRDFs) on the surface read back from the G-buffer of the same view, plus the emission and ambient
// the G-buffer pass computed — so its image is the forward image, and its time the forward pass's
// lighting without the scene's geometry.
layout(set = 2, binding = 4) uniform sampler2D g_emission_ambient;
layout(location = 0) out vec4 out_color;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  Surface s = gbuffer_surface(pixel, texelFetch(g_depth, pixel, 0).r);
  vec3 v = normalize(views[push.view].camera_pos.xyz - s.p);
  vec3 color = texelFetch(g_emission_ambient, pixel, 0).rgb + direct_light(s, v, gl_FragCoord.xy);
  out_color = vec4(color, 1.0);
}
