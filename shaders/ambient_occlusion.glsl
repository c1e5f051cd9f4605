// How ambient occlusion factors combine where the indirect term (ambient, light-map, ambient
// cube) enters: every occlusion contribution of the lighting inputs (lighting_inputs.glsl:
// SSAO today; a baked AO layer would be one more input) takes the minimum, not the product —
// they estimate the same visibility, so a product would count an occluder seen by two of them
// twice (docs/realtime.md "SSAO"). tests/realtime/ssao_test and lighting_inputs_test check
// the rule.
#ifndef ILLUM_AMBIENT_OCCLUSION_GLSL
#define ILLUM_AMBIENT_OCCLUSION_GLSL

float combine_ambient_occlusion(float a, float b) {
  return min(a, b);
}

#endif
