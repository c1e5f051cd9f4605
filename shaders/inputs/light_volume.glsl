// Lighting input `light_volume` (techniques/light_volume.cpp, the worked example of
// docs/realtime-techniques.md): a 3-D volume over the scene's bounds holding, per cell and
// colour channel, the linear irradiance E(n) = a + b·n of the frame's lights at the cell
// centre (no visibility, no bounce). The volume is an atlas of three parts along x (R, G, B),
// each texel (a, b.x, b.y, b.z); sampled trilinearly with the coordinate clamped to the
// part's outer cell centres, so no filter reaches the next part. The volume keeps a history
// copy, and the copies alternate: both are bound and `info.y` names the one its writer wrote
// last. Must match LightVolumeUniforms in techniques/light_volume.cpp.
#ifndef ILLUM_INPUT_LIGHT_VOLUME_GLSL
#define ILLUM_INPUT_LIGHT_VOLUME_GLSL

layout(std140, set = kInputsSet, binding = kLightVolumeInputBase) uniform LightVolumeInput {
  vec4 lo;      // xyz: the volume's min corner; w: strength
  vec4 extent;  // xyz: its size; w: blend (the update pass's)
  ivec4 info;   // x: cells per axis, y: the copy written last, z: 1 where a previous copy holds a frame
  vec4 limits;  // x: the least squared distance to a light (the update pass's)
} light_volume_input;
layout(set = kInputsSet, binding = kLightVolumeInputBase + 1) uniform sampler3D light_volume_copy0;
layout(set = kInputsSet, binding = kLightVolumeInputBase + 2) uniform sampler3D light_volume_copy1;

// Channel `c`'s (a, b) at world point p, trilinear over the cells of copy `copy`.
vec4 light_volume_sample(int copy, int c, vec3 p) {
  float n = float(light_volume_input.info.x);
  vec3 t = clamp((p - light_volume_input.lo.xyz) / light_volume_input.extent.xyz * n, vec3(0.5),
                 vec3(n - 0.5));
  vec3 uvw = vec3((t.x + float(c) * n) / (3.0 * n), t.y / n, t.z / n);
  return copy == 0 ? textureLod(light_volume_copy0, uvw, 0.0)
                   : textureLod(light_volume_copy1, uvw, 0.0);
}

// E(n) per channel at p, clamped at 0 (the linear fit goes negative facing away from a light).
vec3 light_volume_irradiance(vec3 p, vec3 n) {
  int copy = light_volume_input.info.y;
  vec4 r = light_volume_sample(copy, 0, p);
  vec4 g = light_volume_sample(copy, 1, p);
  vec4 b = light_volume_sample(copy, 2, p);
  vec3 e = vec3(r.x + dot(r.yzw, n), g.x + dot(g.yzw, n), b.x + dot(b.yzw, n));
  return max(e, vec3(0.0));
}

void input_light_volume(Surface s, int draw, vec2 frag, inout LightingTerms t) {
  if (!input_active(kLightVolumeInput) || t.has_indirect) return;
  t.indirect = s.albedo * light_volume_irradiance(s.p, s.n) * (light_volume_input.lo.w / kPi);
  t.has_indirect = true;
}

#endif
