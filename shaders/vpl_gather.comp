#version 450
// The virtual point lights' irradiance at every pixel (techniques/vpl.cpp), into
// "vpl.irradiance" (rgb; a = 1 where a surface was seen), which the `vpl` lighting input
// turns into the indirect term (shaders/inputs/vpl.glsl). A diffuse surfel of flux Φ and
// normal n_i has radiant intensity I(ω) = Φ/π · max(0, n_i·ω); at a point p with normal n at
// distance d along ω (from the VPL to p) it gives E = I(ω) · max(0, −n·ω) / d². With the
// clamp c (a distance): E = Φ/π · max(0, n_i·ω) · max(0, −n·ω) / max(d², c²).
//
// The point and its normal come from the depth buffer (the normal from the neighbour
// differences toward the closer neighbour, as the SSAO pyramid takes it: exact on planes).
layout(local_size_x = 8, local_size_y = 8) in;
#include "common.glsl"
#include "vpl_common.glsl"

layout(std140, set = 2, binding = 0) uniform VplGather {
  ivec4 info;    // x: VPLs in the buffer
  vec4 params;   // x: clamp², the minimum squared distance (0: none)
} gather;
layout(set = 2, binding = 1) uniform sampler2D gather_depth;
layout(std430, set = 2, binding = 2) readonly buffer Vpls { Vpl vpls[]; };
layout(set = 2, binding = 3, rgba32f) uniform writeonly image2D irradiance_out;

vec3 position_at(vec2 frag, float depth) {
  vec2 ndc = frag * frame.extent.zw * 2.0 - 1.0;
  vec4 h = frame.inv_view_proj * vec4(ndc, depth, 1.0);
  return h.xyz / h.w;
}

// The difference to the neighbour along `step` whose depth is closer to this pixel's.
vec3 neighbour_difference(ivec2 pixel, ivec2 step, vec3 p, float depth, out bool ok) {
  ivec2 size = ivec2(frame.extent.xy);
  ivec2 a = clamp(pixel + step, ivec2(0), size - 1), b = clamp(pixel - step, ivec2(0), size - 1);
  float da = texelFetch(gather_depth, a, 0).r, db = texelFetch(gather_depth, b, 0).r;
  bool use_a =
      a != pixel && da < 1.0 && (b == pixel || db >= 1.0 || abs(da - depth) <= abs(db - depth));
  ok = use_a || (b != pixel && db < 1.0);
  if (use_a) return position_at(vec2(a) + 0.5, da) - p;
  return p - position_at(vec2(b) + 0.5, db);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  float depth = texelFetch(gather_depth, pixel, 0).r;
  if (depth >= 1.0) {
    imageStore(irradiance_out, pixel, vec4(0.0));
    return;
  }
  vec3 p = position_at(vec2(pixel) + 0.5, depth);
  bool okx, oky;
  vec3 c = cross(neighbour_difference(pixel, ivec2(1, 0), p, depth, okx),
                 neighbour_difference(pixel, ivec2(0, 1), p, depth, oky));
  vec3 to_camera = frame.camera_pos.xyz - p;
  vec3 n = okx && oky && dot(c, c) > 0.0 ? normalize(c) : normalize(to_camera);
  if (dot(n, to_camera) < 0.0) n = -n;
  float clamp2 = gather.params.x;
  vec3 e = vec3(0.0);
  for (int i = 0; i < gather.info.x; ++i) {
    Vpl v = vpls[i];
    vec3 d = p - v.position.xyz;  // d·ω with ω the unit direction from the VPL to p
    float d2 = dot(d, d);
    float cos_sender = dot(v.normal.xyz, d), cos_receiver = -dot(n, d);
    if (cos_sender <= 0.0 || cos_receiver <= 0.0) continue;
    e += v.flux.rgb * (cos_sender * cos_receiver / (d2 * max(d2, clamp2)));
  }
  imageStore(irradiance_out, pixel, vec4(e * (1.0 / kPi), 1.0));
}
