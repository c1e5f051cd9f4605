// The baked-lighting set (set 4, realtime/frame_globals.h kBakedSet), filled by the `baked`
// add-on: light-maps, ambient-cube probes and SH-L1 PRT shown in the ambient term. Must
// match BakedUniforms in realtime/gpu_types.h. When `baked` is off the renderer binds a
// neutral set (kind 0, no PRT, no probed draws).
#ifndef ILLUM_BAKED_GLSL
#define ILLUM_BAKED_GLSL
#include "common.glsl"

layout(std140, set = 4, binding = 0) uniform Baked {
  ivec4 info;        // x: light-map kind (0 none, 1 plain, 2 RNM, 3 SH-L1), y: PRT on,
                     // z: entries of draw_cubes
  vec4 intensity;    // x: light-map intensity
  vec4 prt_light[4]; // PRT: the lights' SH-L1 radiance (Y00, Y1−1, Y10, Y11), RGB
} baked;
// Light-map layers (uv1): 1 = plain, 3 = RNM basis 0..2, 4 = SH-L1 coefficients 0..3.
layout(set = 4, binding = 1) uniform sampler2DArray lightmap;
// Ambient cubes (Source engine): 6 RGB values (+x, −x, +y, −y, +z, −z) per probed draw,
// interpolated on the CPU from the probe grid at the instance's centre.
layout(std430, set = 4, binding = 2) readonly buffer AmbientCubes { vec4 ambient_cubes[]; };
// PRT: per-vertex SH-L1 transfer vectors (Y00, Y1−1, Y10, Y11), indexed by gl_VertexIndex.
layout(std430, set = 4, binding = 3) readonly buffer Transfer { vec4 prt_transfer[]; };
// Per draw (push.view_index of colour passes): its ambient cube + 1, 0 for none.
layout(std430, set = 4, binding = 4) readonly buffer DrawCubes { int draw_cubes[]; };

#endif
