#version 450
// Copies the LPV's accumulated light (float buffer, techniques/lpv.cpp) into "lpv.accum", the
// image the lighting input samples trilinearly: an atlas of three parts along x (R, G, B),
// each texel (c0, c.x, c.y, c.z) of lpv_common.glsl; the cascades one after the other along z.
// It reads each cascade's history (lpv_history.comp), not its latest accumulation. A cascade's
// cells within two of its outermost ones are blended with the next coarser
// cascade, sampled trilinearly at the cell's centre, by weight min(i/2, 1) (i: the cell's
// distance in cells from the outermost layer). The lookup reads the finest cascade holding
// the point, so it fades into the coarser one towards the border with three fetches a pixel,
// not six (more fetches in the frame pipelines' inputs crash lavapipe's compiler now and then).
// A fourth part holds, per cell, the gradient of the DC terms summed over the channels (per
// cell, central differences; one-sided at the faces) and that sum: the lookup's leak
// dampening reads the directional derivative along the normal with one fetch.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "lpv_common.glsl"

layout(std430, set = 0, binding = 4) readonly buffer History { float acc[]; };
layout(set = 0, binding = 9, rgba16f) uniform writeonly image3D accum;

vec4 cell(int q, ivec3 x, int c) {
  int i = lpv_index(q, x, c, 0);
  return vec4(acc[i], acc[i + 1], acc[i + 2], acc[i + 3]);
}

// The DC terms of cell x summed over the colour channels.
float dc(int q, ivec3 x) {
  return acc[lpv_index(q, x, 0, 0)] + acc[lpv_index(q, x, 1, 0)] + acc[lpv_index(q, x, 2, 0)];
}

// Cascade q's light at world point p, trilinear between cell centres, clamped to the outer
// ones.
vec4 trilinear(int q, vec3 p, int c) {
  int n = lpv.info.x;
  vec3 t = clamp((p - lpv.lo[q].xyz) / lpv.lo[q].w, vec3(0.5), vec3(float(n) - 0.5)) - 0.5;
  ivec3 i0 = min(ivec3(floor(t)), ivec3(n - 2));
  vec3 f = t - vec3(i0);
  vec4 sum = vec4(0.0);
  for (int k = 0; k < 8; ++k) {
    ivec3 o = ivec3(k & 1, (k >> 1) & 1, k >> 2);
    vec3 w3 = mix(1.0 - f, f, vec3(o));
    sum += w3.x * w3.y * w3.z * cell(q, i0 + o, c);
  }
  return sum;
}

void main() {
  int n = lpv.info.x;
  ivec3 x = ivec3(gl_GlobalInvocationID);
  int q = x.z / n;
  x.z -= q * n;
  if (any(greaterThanEqual(x, ivec3(n))) || q >= lpv.cascades.x) return;
  ivec3 edge = min(x, ivec3(n - 1) - x);
  float w = q + 1 < lpv.cascades.x ? min(float(min(edge.x, min(edge.y, edge.z))) * 0.5, 1.0) : 1.0;
  vec3 centre = lpv.lo[q].xyz + (vec3(x) + 0.5) * lpv.lo[q].w;
  // Intensity per cell scales with the cell's cross-section (radiance = I/s²): the coarser
  // cascade's, in this cascade's cells, is a quarter.
  float scale = (lpv.lo[q].w * lpv.lo[q].w) /
                (q + 1 < lpv.cascades.x ? lpv.lo[q + 1].w * lpv.lo[q + 1].w : 1.0);
  for (int c = 0; c < 3; ++c) {
    vec4 v = cell(q, x, c);
    if (w < 1.0) v = w * v + (1.0 - w) * scale * trilinear(q + 1, centre, c);
    imageStore(accum, ivec3(x.x + c * n, x.y, q * n + x.z), v);
  }
  vec3 gradient;
  for (int a = 0; a < 3; ++a) {
    ivec3 up = x, down = x;
    up[a] = min(x[a] + 1, n - 1);
    down[a] = max(x[a] - 1, 0);
    gradient[a] = (dc(q, up) - dc(q, down)) / float(up[a] - down[a]);
  }
  imageStore(accum, ivec3(x.x + 3 * n, x.y, q * n + x.z), vec4(gradient, dc(q, x)));
}
