#version 450
// One texel of a reflective shadow map (techniques/rsm.cpp): the surface the light sees there,
// its normal and the flux it reflects diffusely. views[push.view] is the light's view,
// lights[push.light_index] the light. Layout and units: illum/realtime/rsm_views.h.
#define LIGHTING_INPUTS_SURFACE_ONLY
#include "lighting.glsl"
#include "illum/realtime/rsm_views.h"
layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec3 in_prt;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_flux;

void main() {
  Light light = lights[push.light_index];
  int type = int(light.color_type.w);
  View v = views[push.view];
  vec3 to_light = type == kLightDirectional ? -light.direction_cos.xyz
                                            : light.position_range.xyz - in_world;
  vec3 n = normalize(in_normal);
  // The albedo (texture included) and shading normal as every frame pipeline loads them.
  Surface s = load_surface(push.material, in_world, n, in_tangent, in_uv, dot(n, to_light) >= 0.0);
  int size = int(v.extent.x);
  vec3 power;  // the light's flux into this texel: I(ω)·Δω, or E·A for a directional light
  if (v.proj[3][3] == 1.0) {
    // Orthographic: the box's width and height are 2/proj[0][0] and 2/proj[1][1].
    float area = 4.0 / (v.proj[0][0] * v.proj[1][1] * float(size * size));
    power = light.color_type.rgb * area;
  } else {
    float d2 = dot(to_light, to_light);
    float cos_axis = dot(-to_light * inversesqrt(d2), light.direction_cos.xyz);
    float intensity = 1.0;
    // The cone, the cosine of area spots and the radius window, as light_contribution().
    if ((type == kLightSpot || type == kLightLambertian) && cos_axis < light.direction_cos.w)
      intensity = 0.0;
    if (type == kLightLambertian) intensity *= cos_axis;
    float r = light.position_range.w;
    if (r > 0.0) intensity *= max(1.0 - d2 / (r * r), 0.0);
    // Square views: proj[1][1] = 1 / tan(half field of view).
    float t = 1.0 / v.proj[1][1];
    power = light.color_type.rgb * intensity *
            rsm_texel_solid_angle(ivec2(gl_FragCoord.xy), size, t);
  }
  out_position = vec4(in_world, 1.0);
  out_normal = vec4(s.n, 0.0);
  out_flux = vec4(power * s.albedo, 0.0);
}
