// The SSAO add-on's set (slot 2 of its compute and apply layouts, realtime/techniques/
// ssao.cpp): parameters, the depth buffer, the G-buffer's normals where the pipeline has them
// (octahedral RGBA16F: xy shading, zw geometric; a dummy otherwise), a source texture (the
// pyramid's previous level for its downsample, the raw AO for the upsample, the final AO for
// the apply and show passes) and the plane pyramid. Storage images are declared by the
// shaders that write them.
//
// The plane pyramid ("ssao.planes", RGBA32UI, level 0 at full resolution): per texel the
// surface of one pixel as a plane — x: its distance from the camera (float bits; < 0: sky),
// y: dot(s − o, n) (float bits), z: its geometric normal n (10 bits a component: every step
// decodes it, and the offset is taken with the decoded n, so the plane stays exact), w: the
// shading normal (octahedral, packSnorm2x16) — unsigned, so no packed value can be a NaN a
// float path might change —, each coarser level one texel of every 2×2 of the level below
// (rotated grid, so every level keeps exact surfaces, never averages of them).
#ifndef ILLUM_SSAO_SET_GLSL
#define ILLUM_SSAO_SET_GLSL
#include "common.glsl"

// The pyramid's levels (ssao.cpp's kMaxLevels; ssao_prepare.comp's store() names each): level
// m serves taps 2^(m+3) pixels away and more.
const int kSsaoMaxLevels = 6;

layout(std140, set = 2, binding = 0) uniform Ssao {
  vec4 shape;  // radius R, bias b, intensity k, falloff s (scene units)
  ivec4 info;  // directions N, blur radius (pixels), march steps, 1: G-buffer normals bound
  ivec4 grid;  // estimator divisor (1 full, 2 half), pyramid levels, estimates across, down
} ssao;
layout(set = 2, binding = 1) uniform sampler2D ssao_depth;
layout(set = 2, binding = 2) uniform sampler2D ssao_normals;
layout(set = 2, binding = 3) uniform sampler2D ssao_source;
layout(set = 2, binding = 6) uniform usampler2D ssao_planes;

// The surface point at a pixel (its centre) from the depth buffer, as gbuffer.glsl does.
vec3 ssao_position(vec2 frag, float depth) {
  vec2 ndc = frag * frame.extent.zw * 2.0 - 1.0;
  vec4 h = frame.inv_view_proj * vec4(ndc, depth, 1.0);
  return h.xyz / h.w;
}

// The texel below that a texel of a coarser level (or a half-resolution estimate) stands for:
// one of its 2×2 children on a rotated grid (SAO's choice: each level samples every parity).
ivec2 ssao_child(ivec2 texel, ivec2 below) {
  ivec2 c = 2 * texel + ivec2((texel.y & 1) ^ 1, (texel.x & 1) ^ 1);
  return min(c, below - 1);
}
// The pixel an estimate is made at.
ivec2 ssao_representative(ivec2 estimate) {
  ivec2 size = ivec2(frame.extent.xy);
  return ssao.grid.x == 1 ? min(estimate, size - 1) : ssao_child(estimate, size);
}

uint ssao_pack_normal(vec3 n) { return packSnorm2x16(oct_encode(n)); }
vec3 ssao_unpack_normal(uint packed) { return oct_decode(unpackSnorm2x16(packed)); }
uint ssao_pack_plane_normal(vec3 n) {
  uvec3 q = uvec3(round(clamp(n * 0.5 + 0.5, 0.0, 1.0) * 1023.0));
  return q.x | (q.y << 10) | (q.z << 20);
}
// Unit to within 2e-3, not renormalised: every use pairs it with the offset taken with it.
vec3 ssao_unpack_plane_normal(uint packed) {
  return vec3(uvec3(packed, packed >> 10, packed >> 20) & 1023u) * (2.0 / 1023.0) - 1.0;
}

// The geometric normal at a full-resolution pixel: the G-buffer's, or from the depth buffer
// alone — the cross product of the horizontal and vertical position differences, each taken
// toward the neighbour whose depth is closer to this pixel's (so a silhouette next to the
// pixel does not bend it), turned toward the camera. Exact for planar surfaces.
vec3 ssao_depth_neighbour(ivec2 pixel, ivec2 step, vec3 p, float depth, out bool ok) {
  ivec2 size = ivec2(frame.extent.xy);
  ivec2 a = clamp(pixel + step, ivec2(0), size - 1), b = clamp(pixel - step, ivec2(0), size - 1);
  float da = texelFetch(ssao_depth, a, 0).r, db = texelFetch(ssao_depth, b, 0).r;
  bool use_a = a != pixel && da < 1.0 && (b == pixel || db >= 1.0 || abs(da - depth) <= abs(db - depth));
  ok = use_a || (b != pixel && db < 1.0);
  if (use_a) return ssao_position(vec2(a) + 0.5, da) - p;
  return p - ssao_position(vec2(b) + 0.5, db);
}
vec3 ssao_geometric_normal(ivec2 pixel, vec3 p, float depth) {
  if (ssao.info.w != 0) return oct_decode(texelFetch(ssao_normals, pixel, 0).zw);
  bool okx, oky;
  vec3 dx = ssao_depth_neighbour(pixel, ivec2(1, 0), p, depth, okx);
  vec3 dy = ssao_depth_neighbour(pixel, ivec2(0, 1), p, depth, oky);
  vec3 c = cross(dx, dy);
  vec3 to_camera = frame.camera_pos.xyz - p;
  if (!okx || !oky || dot(c, c) <= 0.0) return normalize(to_camera);
  vec3 n = normalize(c);
  return dot(n, to_camera) < 0.0 ? -n : n;
}

#endif
