// The baked-lighting set (set 4, realtime/frame_globals.h kBakedSet), filled by the `baked`
// add-on: light-maps, the probes of dynamic objects (probe_volume.glsl) and PRT shown in the ambient term. Must match
// BakedUniforms in realtime/gpu_types.h. When `baked` is off the renderer binds a neutral
// set (kind 0, no PRT, no probed draws).
#ifndef ILLUM_BAKED_GLSL
#define ILLUM_BAKED_GLSL
#include "common.glsl"

const int kPrtNone = 0, kPrtVertices = 1, kPrtTexels = 2, kPrtVq = 3;  // PrtLookup
const int kProbeLookupPixel = 1;  // baked.probe_size.w (gpu_types.h)

layout(std140, set = 4, binding = 0) uniform Baked {
  ivec4 info;         // x: light-map kind (0 none, 1 plain, 2 RNM, 3 SH-L1, 4 dominant), y: PRT lookup
                      // (kPrt*), z: entries of draw_cubes, w: PRT coefficients (bands²)
  vec4 intensity;     // x: light-map intensity
  ivec4 prt_size;     // PRT: atlas width, height (texels, VQ); z: halves per point
  ivec4 probe_size;   // probe grid nx, ny, nz; w: kProbeLookupPixel, or 0 for the ambient cubes
  vec4 probe_origin;  // xyz: probe (0, 0, 0)
  vec4 probe_spacing; // xyz
  vec4 prt_light[64]; // PRT: the sun's SH radiance coefficients L_i (world frame), RGB
} baked;
// Light-map layers (uv1): 1 = plain, 3 = RNM basis 0..2, 4 = SH-L1 coefficients 0..3,
// 3 = dominant: ambient, directional colour, direction (tangent space).
layout(set = 4, binding = 1) uniform sampler2DArray lightmap;
// Ambient cubes (Source engine): 6 RGB values (+x, −x, +y, −y, +z, −z) per probed draw, the
// CPU's lookup of the probe volume at the instance's centre (baked.probe_lookup=instance).
layout(std430, set = 4, binding = 2) readonly buffer AmbientCubes { vec4 ambient_cubes[]; };
// PRT transfer points (vertices in the scene vertex buffer's order, texels row-major, or VQ
// representatives): per point 3·bands² half floats [coefficient][rgb], two per word,
// padded to prt_size.z halves.
layout(std430, set = 4, binding = 3) readonly buffer Transfer { uint prt_points[]; };
// Per draw (push.view_index of colour passes): its ambient cube + 1, 0 for none.
layout(std430, set = 4, binding = 4) readonly buffer DrawCubes { int draw_cubes[]; };
// PRT VQ: one 16-bit representative index per texel, two per word (low half first).
layout(std430, set = 4, binding = 5) readonly buffer VqIndices { uint prt_vq_indices[]; };
// The probe volume (realtime/probe_volume.h): per probe 27 irradiance SH-L2 coefficients
// E_i [i][rgb], then its validity weight; probe (x, y, z) at record (z·ny + y)·nx + x.
layout(std430, set = 4, binding = 6) readonly buffer ProbeVolume { float probe_data[]; };

#endif
