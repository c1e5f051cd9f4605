// Light propagation volumes (techniques/lpv.cpp, docs/realtime-lpv.md): the block and the
// cell buffers shared by injection, propagation and resolve. The cascades' cells follow each
// other in the buffers, cascade k's n³ cells (and (n+1)³ geometry cells) after cascade k − 1's. A cell's light is, per colour
// channel, the L1 spherical-harmonic expansion of its radiant intensity I(ω) (W/sr):
// I(ω) = c0·Y0 + c·ω·√(3/4π), Y0 = 1/(2√π), stored (c0, c.x, c.y, c.z) — by axis, not in
// the (y, z, x) order of the real SH basis. Its flux is ∫I dω = 2√π·c0.
#ifndef ILLUM_LPV_COMMON_GLSL
#define ILLUM_LPV_COMMON_GLSL

#include "sh.glsl"

const float kLpvPi = 3.14159265358979;
const float kLpvY0 = kShY00;  // 1/(2√π): the one definition in sh.glsl
const float kLpvY1 = kShY1;   // √(3/4π)

// Must match LpvUniforms in techniques/lpv.cpp (std140).
layout(std140, set = 0, binding = 0) uniform LpvParams {
  vec4 lo[4];    // per cascade: xyz its min corner; w its cell size s
  ivec4 info;    // x: cells per axis n; y: surfel images' width, z: height, w: layers
  vec4 far_face; // x: the far face's solid angle ΔΩ; y: ∫ω·d dω over it; zw: unused
  vec4 side_face;  // x: a side face's ΔΩ; y: ∫ω·e dω (e: its outward axis); z: ∫ω·d dω
  ivec4 cascades;  // x: how many; y: bit q set: cascade q is rebuilt this frame; z: bit q set:
                   // its history restarts (first build, or its box moved)
  vec4 blend;      // x: the weight of a rebuild in the history
} lpv;

bool lpv_rebuilt(int q) { return (lpv.cascades.y & (1 << q)) != 0; }

// Flat index of float k of channel c of cell x of cascade q (12 floats per cell).
int lpv_index(int q, ivec3 x, int c, int k) {
  int n = lpv.info.x;
  return ((((q * n + x.z) * n + x.y) * n + x.x) * 3 + c) * 4 + k;
}

// The geometry volume: (n+1)³ cells a cascade centred on its light cells' corners, 4 floats
// each.
int lpv_geometry_index(int q, ivec3 g, int k) {
  int m = lpv.info.x + 1;
  return (((q * m + g.z) * m + g.y) * m + g.x) * 4 + k;
}

#endif
