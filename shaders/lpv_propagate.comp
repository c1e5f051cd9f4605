#version 450
// One LPV propagation step (docs/realtime-lpv.md has the derivation). Each cell gathers from
// its 6 neighbours: light of source cell x − d travelling along d reaches cell x through the
// shared face and leaves it through x's five other faces (the far face, normal d, and four
// side faces, normal e ⊥ d); seen from the source's centre those five cover exactly the
// shared face's solid angle, and the 6·5 faces of the neighbours tile the sphere. The flux
// towards face f is the exact integral Φ_f = ∫_f I(ω) dω = c0·ΔΩ_f·Y0 + √(3/4π)·c·∫_f ω dω
// (lpv.far_face, lpv.side_face: the integrals over the faces, techniques/lpv.cpp), so
// Σ_f Φ_f = 2√π·c0, the source's flux. L1 goes negative behind a lobe: negative face fluxes
// are dropped and the positive ones scaled to sum to the source's flux, so a step neither
// creates nor loses light. Each face's flux becomes, in cell x, a clamped-cosine lobe along
// the face's normal carrying that flux (c0 += Φ_f·Y0, c += Φ_f·n_f/√(3π)), times the
// transmittance at the shared face, 1 − clamp(B(−d), 0, 1): the geometry volume's blocking
// potential B, the mean of its four cells around the face's centre, seen by light moving
// along d. The new light is also added to the accumulation. Every cascade in one dispatch:
// the z of the invocation runs over the cascades' cells one after the other.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "lpv_common.glsl"

layout(std430, set = 0, binding = 1) readonly buffer Source { float src[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Target { float dst[]; };
layout(std430, set = 0, binding = 3) readonly buffer Geometry { float geometry[]; };
layout(std430, set = 0, binding = 4) buffer Accumulation { float acc[]; };

const ivec3 kAxes[6] = ivec3[6](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0), ivec3(0, -1, 0),
                                ivec3(0, 0, 1), ivec3(0, 0, -1));

// Flux of lobe (c0, c) towards a face of the neighbour along d: its far face (normal d), or
// the side face whose outward normal is e.
float face_flux(float c0, vec3 c, vec3 d, vec3 e, bool far) {
  if (far) return c0 * kLpvY0 * lpv.far_face.x + kLpvY1 * lpv.far_face.y * dot(c, d);
  return c0 * kLpvY0 * lpv.side_face.x +
         kLpvY1 * (lpv.side_face.y * dot(c, e) + lpv.side_face.z * dot(c, d));
}

// The axis-aligned unit vectors perpendicular to axis a (index into kAxes).
vec3 side_axis(int a, int k) {
  int axis = a / 2;
  int other = (axis + 1 + k / 2) % 3;
  vec3 e = vec3(0.0);
  e[other] = (k % 2 == 0) ? 1.0 : -1.0;
  return e;
}

// The sum of the positive face fluxes over all 30 faces of the source's neighbours.
float positive_flux(float c0, vec3 c) {
  float sum = 0.0;
  for (int a = 0; a < 6; ++a) {
    vec3 d = vec3(kAxes[a]);
    sum += max(face_flux(c0, c, d, vec3(0.0), true), 0.0);
    for (int k = 0; k < 4; ++k) sum += max(face_flux(c0, c, d, side_axis(a, k), false), 0.0);
  }
  return sum;
}

float blocking(int q, ivec3 x, int a) {
  ivec3 d = kAxes[a];
  int axis = a / 2;
  // The shared face lies on the corner plane x[axis] (d > 0) or x[axis] + 1 (d < 0); its
  // centre is the middle of four geometry cells.
  ivec3 base = x;
  if (d[axis] < 0) base[axis] += 1;
  int u = (axis + 1) % 3, v = (axis + 2) % 3;
  vec4 b = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    ivec3 g = base;
    g[u] += k & 1;
    g[v] += k >> 1;
    for (int j = 0; j < 4; ++j) b[j] += geometry[lpv_geometry_index(q, g, j)];
  }
  b *= 0.25;
  return b.x * kLpvY0 - kLpvY1 * dot(b.yzw, vec3(d));
}

void main() {
  int n = lpv.info.x;
  ivec3 x = ivec3(gl_GlobalInvocationID);
  int q = x.z / n;
  x.z -= q * n;
  if (any(greaterThanEqual(x, ivec3(n))) || q >= lpv.cascades.x || !lpv_rebuilt(q)) return;
  vec4 gathered[3] = vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
  for (int a = 0; a < 6; ++a) {
    ivec3 from = x - kAxes[a];
    if (any(lessThan(from, ivec3(0))) || any(greaterThanEqual(from, ivec3(n)))) continue;
    float transmit = 1.0 - clamp(blocking(q, x, a), 0.0, 1.0);
    if (transmit <= 0.0) continue;
    vec3 d = vec3(kAxes[a]);
    for (int c = 0; c < 3; ++c) {
      float c0 = src[lpv_index(q, from, c, 0)];
      if (c0 <= 0.0) continue;
      vec3 cv = vec3(src[lpv_index(q, from, c, 1)], src[lpv_index(q, from, c, 2)],
                     src[lpv_index(q, from, c, 3)]);
      float total = 2.0 * sqrt(kLpvPi) * c0;
      float positive = positive_flux(c0, cv);
      if (positive <= 0.0) continue;
      float scale = transmit * total / positive;
      float phi = max(face_flux(c0, cv, d, vec3(0.0), true), 0.0) * scale;
      vec4 g = vec4(phi * kLpvY0, phi * d / sqrt(3.0 * kLpvPi));
      for (int k = 0; k < 4; ++k) {
        vec3 e = side_axis(a, k);
        phi = max(face_flux(c0, cv, d, e, false), 0.0) * scale;
        g += vec4(phi * kLpvY0, phi * e / sqrt(3.0 * kLpvPi));
      }
      gathered[c] += g;
    }
  }
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 4; ++k) {
      int i = lpv_index(q, x, c, k);
      dst[i] = gathered[c][k];
      acc[i] += gathered[c][k];
    }
}
