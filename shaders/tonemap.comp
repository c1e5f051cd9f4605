#version 450
// HDR → display: exposure (× the auto exposure luminance_reduce.comp left, when on), a tone
// mapper, bloom added before mapping, sRGB encoding into an 8-bit image.
#include "illum/core/auto_exposure_constants.h"
#include "exposure.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D hdr;
layout(set = 0, binding = 2, rgba8) uniform writeonly image2D ldr;
layout(set = 0, binding = 3) uniform sampler2D bloom;
layout(push_constant) uniform Push {
  int mapper;        // 0 clamp, 1 Reinhard, 2 ACES, 3 AgX
  int auto_exposure; // 1: scale by exposure_data.exposure
  float exposure;
  float bloom_strength;
} push;

vec3 reinhard(vec3 c) {
  float l = dot(c, vec3(0.2126, 0.7152, 0.0722));
  return l > 0.0 ? clamp(c / (1.0 + l), 0.0, 1.0) : vec3(0.0);
}

vec3 aces(vec3 x) {  // Narkowicz 2015 fit (same as core/tonemap.cpp)
  x = max(x, 0.0);
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// AgX (Sobotka): inset to a smaller gamut, log2 encoding over [−12.47, 4.03] EV, a sigmoid
// (6th-order polynomial fit of the reference contrast curve), outset, back to linear.
vec3 agx_contrast(vec3 x) {
  vec3 x2 = x * x;
  vec3 x4 = x2 * x2;
  return 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 +
         0.1191 * x - 0.00232;
}
vec3 agx(vec3 c) {
  const mat3 inset = mat3(0.842479062253094, 0.0423282422610123, 0.0423756549057051,
                          0.0784335999999992, 0.878468636469772, 0.0784336,
                          0.0792237451477643, 0.0791661274605434, 0.879142973793104);
  const mat3 outset = mat3(1.19687900512017, -0.0528968517574562, -0.0529716355144438,
                           -0.0980208811401368, 1.15190312990417, -0.0980434501171241,
                           -0.0990297440797205, -0.0989611768448433, 1.15107367264116);
  const float min_ev = -12.47393, max_ev = 4.026069;
  vec3 v = inset * max(c, 0.0);
  v = clamp(log2(max(v, 1e-10)), min_ev, max_ev);
  v = (v - min_ev) / (max_ev - min_ev);
  v = agx_contrast(v);
  v = outset * v;
  return clamp(pow(max(v, 0.0), vec3(2.2)), 0.0, 1.0);
}

vec3 srgb_encode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
  ivec2 size = textureSize(hdr, 0);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  vec3 c = texelFetch(hdr, p, 0).rgb;
  if (push.bloom_strength > 0.0)
    c += push.bloom_strength * textureLod(bloom, (vec2(p) + 0.5) / vec2(size), 0.0).rgb;
  float scale = push.exposure;
  if (push.auto_exposure != 0) scale *= exposure_data.exposure;
  c *= scale;
  vec3 m;
  if (push.mapper == 1) m = reinhard(c);
  else if (push.mapper == 2) m = aces(c);
  else if (push.mapper == 3) m = agx(c);
  else m = clamp(c, 0.0, 1.0);
  imageStore(ldr, p, vec4(srgb_encode(m), 1.0));
}
