#version 450
// LPV injection (techniques/lpv.cpp, docs/realtime-lpv.md): each texel of the reflective
// shadow map (rsm_views.h: position, normal, flux, one layer per light view) is a virtual
// point light, a clamped-cosine lobe of its flux Φ along its normal, put in the cell holding
// position + ½·s·normal: c0 += Φ/(2√π), c += Φ·n/√(3π). Its surface also goes into the
// geometry volume (the cell centred on the light cells' corner nearest to it) as a blocking
// potential a = A/s² along the normal: b0 += a·√π/2, b += a·√(π/3)·n. Both go into every
// cascade holding them, with that cascade's cell size s.
//
// Float atomics are not core in Vulkan 1.0, 32-bit atomicCompSwap is: each add is a
// compare-and-swap loop on the float's bits — exact float sums on lavapipe and NVIDIA alike,
// and lock-free (one invocation of a conflicting group always succeeds).
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#include "lpv_common.glsl"
#include "illum/realtime/rsm_views.h"

layout(std430, set = 0, binding = 1) buffer Light { uint light[]; };
layout(std430, set = 0, binding = 3) buffer Geometry { uint geometry[]; };
layout(set = 0, binding = 5) uniform sampler2DArray surfel_position;
layout(set = 0, binding = 6) uniform sampler2DArray surfel_normal;
layout(set = 0, binding = 7) uniform sampler2DArray surfel_flux;
layout(std430, set = 0, binding = 8) readonly buffer Views {
  RsmHeader header;
  RsmView views[];
};

// A surfel seen at a grazing angle has a large area behind a small texel; its blocking
// potential is bounded by taking the cosine no smaller than this.
const float kMinCos = 0.2;

void add_light(int i, float v) {
  if (v == 0.0) return;
  uint old = light[i];
  for (;;) {
    uint prev = atomicCompSwap(light[i], old, floatBitsToUint(uintBitsToFloat(old) + v));
    if (prev == old) break;
    old = prev;
  }
}

void add_geometry(int i, float v) {
  if (v == 0.0) return;
  uint old = geometry[i];
  for (;;) {
    uint prev = atomicCompSwap(geometry[i], old, floatBitsToUint(uintBitsToFloat(old) + v));
    if (prev == old) break;
    old = prev;
  }
}

void main() {
  ivec3 t = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(t, lpv.info.yzw))) return;
  vec4 pos = texelFetch(surfel_position, t, 0);
  if (pos.w == 0.0) return;  // nothing seen
  vec3 nrm = texelFetch(surfel_normal, t, 0).xyz;
  float len = length(nrm);
  if (len == 0.0) return;
  nrm /= len;
  vec3 flux = texelFetch(surfel_flux, t, 0).rgb;
  int n = lpv.info.x;

  // The surfel's world area: the texel's footprint on the light's plane (orthographic) or its
  // solid angle times the squared distance (perspective, cube face), over the cosine.
  RsmView view = views[t.z];
  float area;
  if (view.info.w == kRsmViewOrthographic) {
    area = view.direction.w / max(abs(dot(nrm, view.direction.xyz)), kMinCos);
  } else {
    vec3 to = pos.xyz - view.position_type.xyz;
    float d2 = dot(to, to);
    float cosine = d2 > 0.0 ? abs(dot(nrm, to)) * inversesqrt(d2) : 1.0;
    area = rsm_texel_solid_angle(t.xy, header.counts.y, view.direction.w) * d2 /
           max(cosine, kMinCos);
  }

  for (int q = 0; q < lpv.cascades.x; ++q) {
    if (!lpv_rebuilt(q)) continue;
    vec3 lo = lpv.lo[q].xyz;
    float s = lpv.lo[q].w;
    ivec3 cell = ivec3(floor((pos.xyz + 0.5 * s * nrm - lo) / s));
    if (all(greaterThanEqual(cell, ivec3(0))) && all(lessThan(cell, ivec3(n)))) {
      for (int c = 0; c < 3; ++c) {
        float phi = flux[c];
        add_light(lpv_index(q, cell, c, 0), phi * kLpvY0);
        vec3 v = phi * nrm * (1.0 / sqrt(3.0 * kLpvPi));
        add_light(lpv_index(q, cell, c, 1), v.x);
        add_light(lpv_index(q, cell, c, 2), v.y);
        add_light(lpv_index(q, cell, c, 3), v.z);
      }
    }
    ivec3 g = ivec3(floor((pos.xyz - lo) / s + 0.5));
    if (any(lessThan(g, ivec3(0))) || any(greaterThan(g, ivec3(n)))) continue;
    float a = area / (s * s);
    add_geometry(lpv_geometry_index(q, g, 0), a * sqrt(kLpvPi) * 0.5);
    vec3 b = a * sqrt(kLpvPi / 3.0) * nrm;
    add_geometry(lpv_geometry_index(q, g, 1), b.x);
    add_geometry(lpv_geometry_index(q, g, 2), b.y);
    add_geometry(lpv_geometry_index(q, g, 3), b.z);
  }
}
