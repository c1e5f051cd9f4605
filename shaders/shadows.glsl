// Shadow lookups: cube maps of distance (point and spot lights) filtered with PCF over
// rotated Poisson taps, or as variance shadow maps with the light-bleeding threshold τ.
#ifndef ILLUM_SHADOWS_GLSL
#define ILLUM_SHADOWS_GLSL
#include "shadow_set.glsl"

const vec2 kPoisson[16] = vec2[](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725), vec2(-0.09418410, -0.92938870),
    vec2(0.34495938, 0.29387760), vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379), vec2(0.44323325, -0.97511554),
    vec2(0.53742981, -0.47373420), vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590), vec2(0.19984126, 0.78641367),
    vec2(0.14383161, -0.14100790));

float hash12(vec2 p) {
  vec3 p3 = fract(vec3(p.xyx) * 0.1031);
  p3 += dot(p3, p3.yzx + 33.33);
  return fract((p3.x + p3.y) * p3.z);
}

float vsm_visibility(vec2 moments, float t) {
  if (t <= moments.x) return 1.0;
  float variance = max(moments.y - moments.x * moments.x, shadow.params.w);
  float d = t - moments.x;
  float p_max = variance / (variance + d * d);
  // Light-bleeding reduction: map [τ, 1] to [0, 1].
  return clamp((p_max - shadow.params.z) / (1.0 - shadow.params.z), 0.0, 1.0);
}

// Cascaded shadow maps of the (one) shadowed directional light: the cascade is chosen by
// view depth against shadow.cascade_splits; PCF with rotated Poisson taps or VSM.
float cascade_shadow(int i, vec3 p, vec3 ng, vec2 pixel) {
  ShadowLight light = shadow_lights[i];
  float view_depth = -(frame.view * vec4(p, 1.0)).z;
  int cascade = 0;
  while (cascade < light.slot.z - 1 && view_depth > shadow.cascade_splits[cascade]) ++cascade;
  float size = float(textureSize(cascade_maps, 0).x);
  // World size of one texel of this cascade (the shadow-light params hold the ortho half-widths).
  float texel = 2.0 * light.params[cascade] / size;
  vec4 h = shadow_views[light.slot.y + cascade] * vec4(p + ng * texel * 1.5, 1.0);
  vec3 c = h.xyz / h.w;
  vec2 uv = c.xy * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || c.z > 1.0) return 1.0;
  if (shadow.config.x == kShadowVsm)
    return vsm_visibility(texture(cascade_maps, vec3(uv, float(cascade))).rg, c.z);
  float bias = shadow.params.x * 0.1;
  int taps = shadow.config.y;
  if (taps <= 1) return texture(cascade_maps, vec3(uv, float(cascade))).r + bias >= c.z ? 1.0 : 0.0;
  float angle = 6.2831853 * hash12(pixel);
  float cs = cos(angle), sn = sin(angle);
  float lit = 0.0;
  for (int k = 0; k < taps; ++k) {
    vec2 o = kPoisson[k % 16];
    o = vec2(cs * o.x - sn * o.y, sn * o.x + cs * o.y) * shadow.params.y / size;
    lit += texture(cascade_maps, vec3(uv + o, float(cascade))).r + bias >= c.z ? 1.0 : 0.0;
  }
  return lit / float(taps);
}

// Spot light with a 2-D perspective map: the map stores radial distance / far like the cube
// faces, so bias and VSM moments are the same; outside the frustum lies outside the cone.
float spot_shadow(int i, vec3 p, vec3 ng, vec2 pixel) {
  Light light = lights[i];
  ShadowLight sl = shadow_lights[i];
  int slot = sl.slot.x;
  float far_plane = sl.params.x;
  float size = float(textureSize(spot_maps, 0).x);
  float dist = length(p - light.position_range.xyz);
  // World size of one texel at this distance (the map spans 2·tan(half fov) per unit depth).
  float texel = 2.0 * sl.params.y * dist / size;
  vec3 offset_p = p + ng * texel * 1.5;
  vec4 h = shadow_views[sl.slot.y] * vec4(offset_p, 1.0);
  if (h.w <= 0.0) return 1.0;
  vec2 uv = h.xy / h.w * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
  float t = length(offset_p - light.position_range.xyz) / far_plane;
  if (shadow.config.x == kShadowVsm)
    return vsm_visibility(texture(spot_maps, vec3(uv, float(slot))).rg, t);
  float bias = shadow.params.x + texel / far_plane;
  int taps = shadow.config.y;
  if (taps <= 1) return texture(spot_maps, vec3(uv, float(slot))).r + bias >= t ? 1.0 : 0.0;
  float angle = 6.2831853 * hash12(pixel);
  float cs = cos(angle), sn = sin(angle);
  float lit = 0.0;
  for (int k = 0; k < taps; ++k) {
    vec2 o = kPoisson[k % 16];
    o = vec2(cs * o.x - sn * o.y, sn * o.x + cs * o.y) * shadow.params.y / size;
    lit += texture(spot_maps, vec3(uv + o, float(slot))).r + bias >= t ? 1.0 : 0.0;
  }
  return lit / float(taps);
}

// Visibility in [0, 1] of light i from world point p with geometric normal ng.
float cube_shadow(int i, vec3 p, vec3 ng, vec2 pixel) {
  if (shadow.config.x == kShadowNone) return 1.0;  // also stencil volumes: the stencil masks
  Light light = lights[i];
  ShadowLight sl = shadow_lights[i];
  int slot = sl.slot.x;
  if (int(light.color_type.w) == kLightDirectional)
    return sl.slot.z > 0 ? cascade_shadow(i, p, ng, pixel) : 1.0;
  if (slot < 0) return 1.0;
  if (sl.slot.w == 1) return spot_shadow(i, p, ng, pixel);
  vec3 dir = p - light.position_range.xyz;
  float far_plane = sl.params.x;
  float dist = length(dir);
  float size = float(textureSize(shadow_cubes, 0).x);
  // A texel subtends ~2/size of the unit cube face; scale to world units at this distance.
  float texel = 2.0 * dist / size;
  // Normal offset against acne on surfaces seen at grazing angles from the light.
  vec3 offset_p = p + ng * texel * 1.5;
  dir = offset_p - light.position_range.xyz;
  dist = length(dir);
  float t = dist / far_plane;
  if (shadow.config.x == kShadowVsm)
    return vsm_visibility(texture(shadow_cubes, vec4(dir, float(slot))).rg, t);
  float bias = shadow.params.x + texel / far_plane;
  int taps = shadow.config.y;
  if (taps <= 1) return texture(shadow_cubes, vec4(dir, float(slot))).r + bias >= t ? 1.0 : 0.0;
  vec3 axis = dir / dist;
  vec3 u = normalize(cross(abs(axis.y) < 0.99 ? vec3(0, 1, 0) : vec3(1, 0, 0), axis));
  vec3 w = cross(axis, u);
  float angle = 6.2831853 * hash12(pixel);
  float c = cos(angle), sn = sin(angle);
  float radius = shadow.params.y * texel;
  float lit = 0.0;
  for (int k = 0; k < taps; ++k) {
    vec2 o = kPoisson[k % 16];
    o = vec2(c * o.x - sn * o.y, sn * o.x + c * o.y) * radius;
    vec3 d = dir + u * o.x + w * o.y;
    lit += texture(shadow_cubes, vec4(d, float(slot))).r + bias >= t ? 1.0 : 0.0;
  }
  return lit / float(taps);
}

#endif
