// The lighting inputs (set 4, realtime/lighting_inputs.h): every registered input's module
// (inputs/<name>.glsl: its bindings at its base, one input_<name>()) and the one hook the
// frame pipelines call, gather_lighting_inputs(). Bindings: lighting_inputs_bindings.h, shared
// with the C++. An input whose flag is 0 (no active technique contributes it) returns at once.
//
// Terms: `indirect` (irradiance × albedo) comes from the first input that gives one for the
// surface, in the order below (a probed dynamic object takes the probes even where a
// light-map is bound); `indirect_has_visibility` says it already holds the surface's own
// visibility (PRT transfer); occlusions combine by minimum (ambient_occlusion.glsl);
// `specular` and `extra` add radiance (environment maps; no input fills them yet).
//
// The deferred pipeline's G-buffer pass runs before the screen-space phase: it defines
// LIGHTING_INPUTS_SURFACE_ONLY and a later pass (deferred_inputs.comp) gathers the
// screen-space inputs with LIGHTING_INPUTS_SCREEN_ONLY.
#ifndef ILLUM_LIGHTING_INPUTS_GLSL
#define ILLUM_LIGHTING_INPUTS_GLSL
#include "illum/realtime/lighting_inputs_bindings.h"
#include "ambient_occlusion.glsl"

layout(std140, set = kInputsSet, binding = kInputsStateBinding) uniform InputsState {
  ivec4 flags[kMaxLightingInputs / 4];
} inputs_state;

bool input_active(int index) {
  return inputs_state.flags[index / 4][index % 4] != 0;
}

struct LightingTerms {
  vec3 indirect;                 // irradiance × albedo, radiance units
  bool has_indirect;             // an input gave `indirect` (else: albedo · frame.ambient)
  bool indirect_has_visibility;  // `indirect` holds the surface's visibility: no occlusion
  float occlusion;               // 1 = open; the minimum of the occlusion inputs
  vec3 specular;                 // indirect specular radiance
  vec3 extra;                    // any other radiance
};

#define ILLUM_LIGHTING_TERMS
#include "inputs/probes.glsl"
#include "inputs/prt.glsl"
#include "inputs/lightmap.glsl"
#include "inputs/ssao.glsl"
#include "inputs/light_volume.glsl"
#include "inputs/lpv.glsl"
#include "inputs/vpl.glsl"

LightingTerms gather_lighting_inputs(Surface s, int draw, vec2 frag) {
  LightingTerms t;
  t.indirect = vec3(0.0);
  t.has_indirect = false;
  t.indirect_has_visibility = false;
  t.occlusion = 1.0;
  t.specular = vec3(0.0);
  t.extra = vec3(0.0);
#ifndef LIGHTING_INPUTS_SCREEN_ONLY
  input_probes(s, draw, frag, t);
  input_prt(s, draw, frag, t);
  input_lightmap(s, draw, frag, t);
  input_light_volume(s, draw, frag, t);
  input_lpv(s, draw, frag, t);
#endif
#ifndef LIGHTING_INPUTS_SURFACE_ONLY
  input_vpl(s, draw, frag, t);
  input_ssao(s, draw, frag, t);
#endif
  return t;
}

// The occlusion the indirect term takes: none where it already holds the visibility (SSAO
// must not darken PRT twice: docs/realtime.md "SSAO").
float indirect_occlusion(LightingTerms t) {
  return t.has_indirect && t.indirect_has_visibility ? 1.0 : t.occlusion;
}

#endif
