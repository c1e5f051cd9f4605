#version 450
// Screen-space ambient occlusion with Méndez's term (S001 §4.3, ALGORITHMS.md item 26), one
// estimate per pixel, or at half resolution at one pixel of each 2×2: N directions ω uniform over the hemisphere around the
// normal (stratified in cos θ; azimuths on a golden-angle sequence turned per pixel by a 4×4
// interleaved rotation), each marched from the surface point p to the radius R in `steps`
// jittered steps; the first step that falls behind the visible surface (within the
// thickness R) ends the march at the hit distance t, and the direction adds
//   saturate(N·ω − b) / (1 + (t/s)²).
// With the uniform pdf 1/2π the occlusion O = (2/N) Σ terms estimates
//   (1/π) ∫ V_R(ω) max(cos θ − b, 0) / (1 + (t/s)²) dω,
// the estimand of the offline `ao` integrator with bias b and falloff s; AO = 1 − k·O.
// The visible surface behind a step is the plane of the pyramid texel under it (near steps
// read level 0, farther ones coarser levels, so wide radii stay in the cache) extended to the
// step's camera ray: planar occluders are compared at sub-pixel precision, and the hit is
// where the ray crosses that plane (exact for planes; bisection where the crossing lies
// outside the last step, at edges). Steps are projected incrementally: clip(p + tω) =
// clip(p) + t·clip(ω) (in homogeneous pixels), and a direction's texels are all fetched before its march, so the
// fetches overlap rather than each waiting for the previous step's answer.
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, r32f) uniform writeonly image2D ao_out;

// Steps along each direction (ssao.cpp's kMarchSteps): a compile-time count, so the fetches
// unroll.
const int kSteps = 6;

// Taps nearer than 2^kDenseLog2 pixels read level 0 (exact per pixel); each doubling of the distance one
// level coarser (SAO's rule).
const int kDenseLog2 = 3;

uint hash(uint x) {  // PCG-style integer hash
  x = x * 747796405u + 2891336453u;
  x = ((x >> ((x >> 28u) + 4u)) ^ x) * 277803737u;
  return (x >> 22u) ^ x;
}
float random(inout uint state) {
  state = hash(state);
  return float(state >> 8) * (1.0 / 16777216.0);
}

// A point's homogeneous pixel position (x, y, w: pixel = xy/w) from its clip position: linear
// in the point, so a ray's steps are clip(p) + t·clip(ω) mapped once.
vec3 to_pixels(vec4 clip) {
  return vec3((clip.xy + clip.w) * (0.5 * frame.extent.xy), clip.w);
}

// The pyramid texel and level under the point at homogeneous pixel position h; level −1:
// off screen or behind the camera (screen space knows nothing there: the march ends
// unoccluded). Level floor(log2 d) − kDenseLog2 for d pixels from the origin, from d²'s
// exponent (no root, no logarithm).
ivec3 locate(vec3 h, vec2 origin) {
  if (h.z <= 0.0) return ivec3(0, 0, -1);
  vec2 px = h.xy * (1.0 / h.z);
  if (any(lessThan(px, vec2(0.0))) || any(greaterThan(px, frame.extent.xy)))
    return ivec3(0, 0, -1);
  vec2 d = px - origin;
  int level = clamp((findMSB(uint(dot(d, d))) >> 1) - kDenseLog2, 0, ssao.grid.y - 1);
  ivec2 size = max(ivec2(frame.extent.xy) >> level, ivec2(1));
  return ivec3(min(ivec2(px) >> level, size - 1), level);
}

// 1: the point q (qo = q − camera) lies behind the visible surface of texel v (of `level`)
// within the thickness R; 0: in front of it or the texel shows the sky. n, plane_d: the
// texel's plane (dot(x − o, n) = plane_d).
int compare(uvec4 v, int level, vec3 qo, float radius, out vec3 n, out float plane_d) {
  n = vec3(0.0);
  plane_d = 0.0;
  float dist_s = uintBitsToFloat(v.x);
  if (dist_s < 0.0) return 0;
  n = ssao_unpack_plane_normal(v.z);
  plane_d = uintBitsToFloat(v.y);
  float q2 = dot(qo, qo);
  float dist_q = q2 * inversesqrt(q2);
  float qn = dot(qo, n);  // cos θ_ray · dist_q
  float inv_qn = 1.0 / qn;
  bool slanted = abs(qn) > 0.05 * dist_q;
  // Along q's camera ray to the plane (grazing planes: the texel's own distance).
  float along = slanted ? plane_d * dist_q * inv_qn : dist_s;
  // No farther from the texel's point than four pixel footprints (one is 2d/(H·|P11|)) plus
  // the depth its plane gains across the texel's span of pixels (the point's pixel may lie
  // that far from q's; 1/max(|cos|, 0.05) per footprint on a slanted plane): a plane seen
  // edge-on or another surface's texel would otherwise move it arbitrarily.
  float inv_cos = slanted ? dist_q * abs(inv_qn) : 20.0;
  float pixel = 2.0 * dist_s * frame.extent.w / max(abs(frame.proj[1][1]), 1e-6);
  float reach = pixel * (4.0 + float((1 << level) - 1) * inv_cos);
  along = clamp(along, dist_s - reach, dist_s + reach);
  return along < dist_q * (1.0 - 1e-4) && dist_q - along < radius ? 1 : 0;
}

// compare() at any point of the ray, −1 off screen.
int behind(vec3 h, vec3 qo, float radius, vec2 origin, out vec3 n, out float plane_d) {
  ivec3 cell = locate(h, origin);
  n = vec3(0.0);
  plane_d = 0.0;
  if (cell.z < 0) return -1;
  return compare(texelFetch(ssao_planes, cell.xy, cell.z), cell.z, qo, radius, n, plane_d);
}

// Ranks of the 4×4 Bayer matrix: neighbouring pixels' rotations differ most.
const uint kBayer[16] = uint[](0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, ssao.grid.zw))) return;
  ivec2 pixel = ssao_representative(texel);
  uvec4 v = texelFetch(ssao_planes, pixel, 0);
  if (uintBitsToFloat(v.x) < 0.0) {
    imageStore(ao_out, texel, vec4(1.0));
    return;
  }
  vec3 p = ssao_position(vec2(pixel) + 0.5, texelFetch(ssao_depth, pixel, 0).r);
  vec3 n = ssao_unpack_normal(v.w);  // the shading normal
  vec3 t = normalize(abs(n.x) > 0.5 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
  vec3 b = cross(n, t);
  float radius = ssao.shape.x, bias = ssao.shape.y, falloff = ssao.shape.w;
  int directions = ssao.info.x;
  uint state = hash(uint(pixel.x) * 1973u + hash(uint(pixel.y) * 9277u));
  // Each azimuth stays uniform (the rotation is uniform over the circle: a Bayer rank jittered
  // within its sixteenth), and a pixel's azimuths are spread by the golden angle.
  float rotation = (float(kBayer[(texel.y & 3) * 4 + (texel.x & 3)]) + random(state)) / 16.0;
  vec2 origin = vec2(pixel) + 0.5;
  vec3 po = p - frame.camera_pos.xyz;
  vec3 h_p = to_pixels(frame.view_proj * vec4(p, 1.0));
  float sum = 0.0;
  for (int i = 0; i < directions; ++i) {
    float cos_theta = (float(i) + random(state)) / float(directions);
    float phi = 2.0 * kPi * fract(rotation + 0.6180339887 * float(i));
    float jitter = random(state);
    float term = clamp(cos_theta - bias, 0.0, 1.0);
    if (term <= 0.0) continue;  // adds nothing whatever it hits
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    vec3 w = (t * cos(phi) + b * sin(phi)) * sin_theta + n * cos_theta;
    vec3 h_w = to_pixels(frame.view_proj * vec4(w, 0.0));
    int levels[kSteps + 1];
    uvec4 texels[kSteps + 1];
    [[unroll]] for (int j = 0; j <= kSteps; ++j) {
      float step_t = radius * min((float(j) + jitter) / float(kSteps), 1.0);
      ivec3 cell = locate(h_p + step_t * h_w, origin);
      levels[j] = cell.z;
      texels[j] = texelFetch(ssao_planes, cell.xy, max(cell.z, 0));
    }
    float free_t = 0.0;
    [[unroll]] for (int j = 0; j <= kSteps; ++j) {
      float step_t = radius * min((float(j) + jitter) / float(kSteps), 1.0);
      if (levels[j] < 0) break;
      vec3 hn;
      float hd;
      int r = compare(texels[j], levels[j], po + w * step_t, radius, hn, hd);
      if (r == 0) {
        free_t = step_t;
        continue;
      }
      float lo = free_t, hi = step_t;  // lo in front, hi behind
      float wn = dot(w, hn);
      float t_plane = wn < 0.0 ? (hd - dot(po, hn)) / wn : -1.0;
      if (t_plane >= lo && t_plane <= hi) {
        hi = t_plane;
      } else {
        for (int k = 0; k < 6; ++k) {
          float mid = 0.5 * (lo + hi);
          if (behind(h_p + mid * h_w, po + w * mid, radius, origin, hn, hd) == 1) hi = mid;
          else lo = mid;
        }
      }
      float d = falloff > 0.0 ? hi / falloff : 0.0;
      sum += term / (1.0 + d * d);
      break;
    }
  }
  float occlusion = 2.0 * sum / float(directions);
  imageStore(ao_out, texel, vec4(clamp(1.0 - ssao.shape.z * occlusion, 0.0, 1.0)));
}
