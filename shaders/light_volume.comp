#version 450
// The `light_volume` add-on's update (techniques/light_volume.cpp): per cell, the linear
// irradiance E(n) = a + b·n of the frame's lights at the cell centre, unshadowed. A light that
// gives irradiance Φ to a surface facing it from unit direction l gives E(n) = Φ·max(0, n·l);
// its projection on SH bands 0 and 1 (the least-squares fit by a + b·n over the sphere) is
// a = Φ/4, b = Φ/2 · l. The distance is clamped below at half a cell (limits.x) so a light at
// a cell centre stays finite in half floats.
// With a previous copy the cell moves towards that target by `blend`:
// V = V.previous + blend · (target − V.previous).
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "common.glsl"

layout(set = 2, binding = 0, rgba16f) uniform writeonly image3D volume;    // "light_volume"
layout(set = 2, binding = 1, rgba16f) uniform readonly image3D previous;   // ".previous"
layout(std140, set = 2, binding = 2) uniform LightVolumeInput {
  vec4 lo;      // xyz: the volume's min corner; w: strength
  vec4 extent;  // xyz: its size; w: blend
  ivec4 info;   // x: cells per axis, y: the copy written last, z: 1 where a previous copy holds a frame
  vec4 limits;  // x: the least squared distance to a light
} u;

void main() {
  int n = u.info.x;
  ivec3 cell = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(cell, ivec3(n)))) return;
  vec3 p = u.lo.xyz + (vec3(cell) + 0.5) * u.extent.xyz / float(n);
  vec3 a = vec3(0.0);
  mat3 b = mat3(0.0);  // b[c]: channel c's gradient
  for (int i = 0; i < frame.counts.x; ++i) {
    Light light = lights[i];
    int type = int(light.color_type.w);
    vec3 l;
    float atten = 1.0;
    if (type == kLightDirectional) {
      l = -light.direction_cos.xyz;
    } else {
      // lighting.glsl's light_contribution: inverse square, radius window, cone.
      vec3 to = light.position_range.xyz - p;
      float d2 = dot(to, to);
      float r = light.position_range.w;
      if (r > 0.0 && d2 >= r * r) continue;
      l = to * inversesqrt(d2);
      atten = 1.0 / max(d2, u.limits.x);
      if (r > 0.0) atten *= max(1.0 - d2 / (r * r), 0.0);
      float cos_axis = dot(-l, light.direction_cos.xyz);
      if ((type == kLightSpot || type == kLightLambertian) && cos_axis < light.direction_cos.w)
        continue;
      if (type == kLightLambertian) atten *= cos_axis;
    }
    vec3 phi = light.color_type.rgb * atten;
    a += 0.25 * phi;
    for (int c = 0; c < 3; ++c) b[c] += 0.5 * phi[c] * l;
  }
  for (int c = 0; c < 3; ++c) {
    ivec3 at = ivec3(cell.x + c * n, cell.y, cell.z);
    vec4 target = vec4(a[c], b[c]);
    vec4 v = u.info.z != 0 ? mix(imageLoad(previous, at), target, u.extent.w) : target;
    imageStore(volume, at, v);
  }
}
