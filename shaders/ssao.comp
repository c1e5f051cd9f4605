#version 450
// Screen-space ambient occlusion with Méndez's term (S001 §4.3, ALGORITHMS.md item 26): N
// directions ω uniform over the hemisphere around the normal (stratified in cos θ, a random
// azimuth per pixel and direction), each marched from the surface point p to the radius R
// in `steps` jittered steps; the first step that falls behind the depth buffer (within the
// thickness R) is refined by bisection to the hit distance t, and the direction adds
//   saturate(N·ω − b) / (1 + (t/s)²).
// With the uniform pdf 1/2π the occlusion O = (2/N) Σ terms estimates
//   (1/π) ∫ V_R(ω) max(cos θ − b, 0) / (1 + (t/s)²) dω,
// the estimand of the offline `ao` integrator with bias b and falloff s; AO = 1 − k·O.
// The surface behind a step's pixel is its depth-buffer point extended along that point's
// geometric normal to the step's camera ray, so planar occluders are compared at sub-pixel
// precision (no self-occlusion from the depth buffer's stair steps).
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, r32f) uniform writeonly image2D ao_out;

uint hash(uint x) {  // PCG-style integer hash
  x = x * 747796405u + 2891336453u;
  x = ((x >> ((x >> 28u) + 4u)) ^ x) * 277803737u;
  return (x >> 22u) ^ x;
}
float random(inout uint state) {
  state = hash(state);
  return float(state >> 8) * (1.0 / 16777216.0);
}

// 1: q lies behind the visible surface (within the thickness R); 0: in front of it or the
// pixel shows the sky; −1: q is off screen or behind the camera (screen space knows nothing
// there: the march ends unoccluded).
int behind(vec3 q, float radius) {
  vec4 clip = frame.view_proj * vec4(q, 1.0);
  if (clip.w <= 0.0) return -1;
  vec2 ndc = clip.xy / clip.w;
  if (any(greaterThan(abs(ndc), vec2(1.0)))) return -1;
  ivec2 pixel = min(ivec2((ndc * 0.5 + 0.5) * frame.extent.xy), ivec2(frame.extent.xy) - 1);
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  if (depth >= 1.0) return 0;
  vec3 s = ssao_position(vec2(pixel) + 0.5, depth);
  vec3 o = frame.camera_pos.xyz;
  float dist_q = distance(o, q);
  vec3 ray = (q - o) / dist_q;
  float dist_s = distance(o, s);
  vec3 n = ssao_geometric_normal(pixel);
  float cos_ray = dot(ray, n);
  // Along q's camera ray to the plane through s (grazing planes: s's own distance).
  float along = abs(cos_ray) > 0.05 ? dot(s - o, n) / cos_ray : dist_s;
  // No farther from s than four pixel footprints (2d/(H·|P11|) each): a plane seen edge-on
  // or another surface's texel would otherwise move it arbitrarily.
  float footprint = 8.0 * dist_s * frame.extent.w / max(abs(frame.proj[1][1]), 1e-6);
  along = clamp(along, dist_s - footprint, dist_s + footprint);
  float eps = 1e-4 * dist_q;
  return along < dist_q - eps && dist_q - along < radius ? 1 : 0;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  float depth = texelFetch(ssao_depth, pixel, 0).r;
  if (depth >= 1.0) {
    imageStore(ao_out, pixel, vec4(1.0));
    return;
  }
  vec3 p = ssao_position(vec2(pixel) + 0.5, depth);
  vec3 n = oct_decode(texelFetch(ssao_normals, pixel, 0).xy);
  vec3 t = normalize(abs(n.x) > 0.5 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
  vec3 b = cross(n, t);
  float radius = ssao.shape.x, bias = ssao.shape.y, falloff = ssao.shape.w;
  int directions = ssao.info.x, steps = ssao.info.z;
  uint state = hash(uint(pixel.x) * 1973u + hash(uint(pixel.y) * 9277u));
  float sum = 0.0;
  for (int i = 0; i < directions; ++i) {
    float cos_theta = (float(i) + random(state)) / float(directions);
    float phi = 2.0 * kPi * random(state);
    float jitter = random(state);
    float term = clamp(cos_theta - bias, 0.0, 1.0);
    if (term <= 0.0) continue;  // adds nothing whatever it hits
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    vec3 w = (t * cos(phi) + b * sin(phi)) * sin_theta + n * cos_theta;
    float free_t = 0.0;
    for (int j = 0; j <= steps; ++j) {
      float step_t = radius * min((float(j) + jitter) / float(steps), 1.0);
      int r = behind(p + w * step_t, radius);
      if (r < 0) break;
      if (r == 0) {
        free_t = step_t;
        continue;
      }
      float lo = free_t, hi = step_t;  // bisection: lo in front, hi behind
      for (int k = 0; k < 5; ++k) {
        float mid = 0.5 * (lo + hi);
        if (behind(p + w * mid, radius) == 1) hi = mid; else lo = mid;
      }
      float d = falloff > 0.0 ? hi / falloff : 0.0;
      sum += term / (1.0 + d * d);
      break;
    }
  }
  float occlusion = 2.0 * sum / float(directions);
  imageStore(ao_out, pixel, vec4(clamp(1.0 - ssao.shape.z * occlusion, 0.0, 1.0)));
}
