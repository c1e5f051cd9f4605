// How ambient occlusion factors combine where the indirect terms (ambient, light-map,
// ambient cube, PRT) enter: screen-space AO with a baked AO layer takes the minimum, not
// the product — both estimate the same visibility, so a product would count an occluder
// seen by both twice (docs/realtime.md "SSAO"). tests/realtime/ssao_test checks the rule.
#ifndef ILLUM_AMBIENT_OCCLUSION_GLSL
#define ILLUM_AMBIENT_OCCLUSION_GLSL

float combine_ambient_occlusion(float screen_space, float baked) {
  return min(screen_space, baked);
}

// The baked AO layer's factor at a surface; no such layer exists yet (1 = unoccluded). A
// baked AO light-map layer would be read here (baked.glsl, uv1).
float baked_ambient_occlusion() {
  return 1.0;
}

#endif
