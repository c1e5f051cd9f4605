// Lighting input `probes` (techniques/baked.cpp): the probes of dynamic objects. A probed
// draw (draw_cubes[draw] > 0) takes, per pixel, albedo·E(n)/π of the probe volume
// (probe_volume.glsl), or its ambient cube along the normal (baked.probe_lookup=instance).
// Must match ProbesInputUniforms in realtime/gpu_types.h.
#ifndef ILLUM_INPUT_PROBES_GLSL
#define ILLUM_INPUT_PROBES_GLSL
#include "sh.glsl"

const int kProbeLookupPixel = 1;  // probes_input.size.w (gpu_types.h)

layout(std140, set = kInputsSet, binding = kProbesInputBase) uniform ProbesInput {
  ivec4 size;     // probe grid nx, ny, nz; w: kProbeLookupPixel, or 0 for the ambient cubes
  vec4 origin;    // xyz: probe (0, 0, 0)
  vec4 spacing;   // xyz
  ivec4 info;     // x: entries of draw_cubes
} probes_input;
// Ambient cubes (Source engine): 6 RGB values (+x, −x, +y, −y, +z, −z) per probed draw, the
// CPU's lookup of the probe volume at the instance's centre (baked.probe_lookup=instance).
layout(std430, set = kInputsSet, binding = kProbesInputBase + 1) readonly buffer AmbientCubes {
  vec4 ambient_cubes[];
};
// Per draw (push.draw of colour passes): its ambient cube + 1, 0 for none.
layout(std430, set = kInputsSet, binding = kProbesInputBase + 2) readonly buffer DrawCubes {
  int draw_cubes[];
};
// The probe volume (realtime/probe_volume.h): per probe 27 irradiance SH-L2 coefficients
// E_i [i][rgb], then its validity weight; probe (x, y, z) at record (z·ny + y)·nx + x.
layout(std430, set = kInputsSet, binding = kProbesInputBase + 3) readonly buffer ProbeVolume {
  float probe_data[];
};

#include "probe_volume.glsl"

void input_probes(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kProbesInput) || t.has_indirect) return;
  int cube = draw < probes_input.info.x ? draw_cubes[draw] : 0;
  if (cube <= 0) return;
  t.has_indirect = true;
  if (probes_input.size.w == kProbeLookupPixel) {
    t.indirect = s.albedo * kShInvPi * max(probe_volume_irradiance(s.p, s.n, s.ng), 0.0);
    return;
  }
  int base = 6 * (cube - 1);
  vec3 n2 = s.n * s.n;
  vec3 a = n2.x * ambient_cubes[base + (s.n.x >= 0.0 ? 0 : 1)].rgb +
           n2.y * ambient_cubes[base + (s.n.y >= 0.0 ? 2 : 3)].rgb +
           n2.z * ambient_cubes[base + (s.n.z >= 0.0 ? 4 : 5)].rgb;
  t.indirect = s.albedo * a;
}

#endif
