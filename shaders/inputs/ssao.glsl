// Lighting input `ssao` (techniques/ssao.cpp): the frame's screen-space occlusion image
// "ssao" at the output resolution, R channel, 1 = open, read at the pixel.
#ifndef ILLUM_INPUT_SSAO_GLSL
#define ILLUM_INPUT_SSAO_GLSL

layout(set = kInputsSet, binding = kSsaoInputBase) uniform sampler2D ssao_image;

void input_ssao(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kSsaoInput)) return;
  float a = texelFetch(ssao_image, ivec2(frag), 0).r;
  t.occlusion = combine_ambient_occlusion(t.occlusion, a);
}

#endif
