#version 450
// Test kernel (tests/realtime/lighting_inputs_test): two occlusion contributions through the
// lighting inputs' own code — the `ssao` input's module, run at two pixels of its image on one
// LightingTerms as two inputs would — combine by minimum; its flag at 0 leaves the term open.
// Bindings used: set 4's state block and the ssao image, set 2 the cases and results.
layout(local_size_x = 64) in;
#include "lighting.glsl"
layout(std430, set = 2, binding = 0) readonly buffer Cases { ivec4 cases[]; };  // two pixels
layout(std430, set = 2, binding = 1) writeonly buffer Results { vec2 results[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(push.material)) return;  // push.material: the case count
  Surface s;
  LightingTerms t;
  t.indirect = vec3(0.0);
  t.has_indirect = false;
  t.indirect_has_visibility = false;
  t.occlusion = 1.0;
  t.specular = vec3(0.0);
  t.extra = vec3(0.0);
  input_ssao(s, 0, vec2(cases[i].xy) + 0.5, t);
  input_ssao(s, 0, vec2(cases[i].zw) + 0.5, t);
  results[i] = vec2(t.occlusion, indirect_occlusion(t));
}
