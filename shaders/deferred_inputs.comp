#version 450
// Deferred: the screen-space lighting inputs (SSAO), applied over the HDR target once the
// screen-space phase has written them. The G-buffer pass (gbuffer_pass.glsl) gathered the
// surface inputs and wrote emission + indirect·o_s (+ specular, extra) into the HDR target and
// the indirect term with o_s into "gbuffer.indirect"; this pass adds
// indirect·(min(o_s, o_screen) − o_s), so the frame holds what the forward and visibility
// pipelines' single gather gives: indirect × the minimum of the occlusions.
layout(local_size_x = 8, local_size_y = 8) in;
#define LIGHTING_INPUTS_SCREEN_ONLY
#include "gbuffer.glsl"
layout(set = 2, binding = 4, rgba16f) uniform image2D hdr_image;
layout(set = 2, binding = 5) uniform sampler2D g_indirect;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  float depth = texelFetch(g_depth, pixel, 0).r;
  if (depth >= 1.0) return;
  vec4 g = texelFetch(g_indirect, pixel, 0);
  if (g.a < 0.0) return;  // the indirect term holds its own visibility (PRT)
  Surface s = gbuffer_surface(pixel, depth);
  LightingTerms t = gather_lighting_inputs(s, 0, vec2(pixel) + 0.5);
  float occlusion = combine_ambient_occlusion(g.a, t.occlusion);
  if (occlusion == g.a) return;
  vec4 c = imageLoad(hdr_image, pixel);
  imageStore(hdr_image, pixel, vec4(c.rgb + g.rgb * (occlusion - g.a), c.a));
}
