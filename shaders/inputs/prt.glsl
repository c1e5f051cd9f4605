// Lighting input `prt` (techniques/baked.cpp): PRT transfer relit by the sun (prt.glsl
// decodes it). The transfer holds all the light the surface receives (direct and, when
// interreflected, bounced) and its own visibility, so no occlusion input darkens it. Must
// match PrtInputUniforms in realtime/gpu_types.h. forward.vert includes this file for the
// per-vertex lookup (without the input function, which needs lighting.glsl's Surface).
#ifndef ILLUM_INPUT_PRT_GLSL
#define ILLUM_INPUT_PRT_GLSL
#include "illum/realtime/lighting_inputs_bindings.h"

const int kPrtNone = 0, kPrtVertices = 1, kPrtTexels = 2, kPrtVq = 3;  // PrtLookup

layout(std140, set = kInputsSet, binding = kPrtInputBase) uniform PrtInput {
  ivec4 info;      // x: lookup (kPrt*), y: coefficients (bands²)
  ivec4 size;      // atlas width, height (texels, VQ); z: halves per point
  vec4 light[64];  // the sun's SH radiance coefficients L_i (world frame), RGB
} prt_input;
// Transfer points (vertices in the scene vertex buffer's order, texels row-major, or VQ
// representatives): per point 3·bands² half floats [coefficient][rgb], two per word,
// padded to prt_input.size.z halves.
layout(std430, set = kInputsSet, binding = kPrtInputBase + 1) readonly buffer Transfer {
  uint prt_points[];
};
// VQ: one 16-bit representative index per texel, two per word (low half first).
layout(std430, set = kInputsSet, binding = kPrtInputBase + 2) readonly buffer VqIndices {
  uint prt_vq_indices[];
};

#include "../prt.glsl"

#ifdef ILLUM_LIGHTING_TERMS
void input_prt(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kPrtInput) || t.has_indirect || prt_input.info.x == kPrtNone) return;
  vec3 e = prt_input.info.x == kPrtVertices ? s.prt_vertex : prt_atlas_relit(s.uv1);
  t.indirect = s.albedo * max(e, 0.0);
  t.has_indirect = true;
  t.indirect_has_visibility = true;
}
#endif

#endif
