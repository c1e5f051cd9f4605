// Lighting input `vpl` (techniques/vpl.cpp, docs/realtime-vpl.md): the virtual point lights'
// irradiance E at the pixel, "vpl.irradiance" (rgb), summed per pixel by a compute pass of the
// screen-space phase so that no loop over the lights is compiled into the frame pipelines.
// The indirect term is albedo·E/π, in place of albedo × ambient.
#ifndef ILLUM_INPUT_VPL_GLSL
#define ILLUM_INPUT_VPL_GLSL

layout(set = kInputsSet, binding = kVplInputBase) uniform sampler2D vpl_irradiance;

void input_vpl(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kVplInput) || t.has_indirect) return;
  t.indirect = s.albedo * texelFetch(vpl_irradiance, ivec2(frag), 0).rgb * (1.0 / kPi);
  t.has_indirect = true;
}

#endif
