#version 450
#include "shadow_set.glsl"
// Distance to the light over the far distance, and its square (VSM moments).
layout(location = 0) in vec3 in_world;
layout(location = 0) out vec2 out_moments;
void main() {
  Light light = lights[push.light_index];
  float t = length(in_world - light.position_range.xyz) / shadow_lights[push.light_index].params.x;
  // The second moment includes the in-texel slope (Donnelly & Lauritzen) against VSM acne.
  float dx = dFdx(t), dy = dFdy(t);
  out_moments = vec2(t, t * t + 0.25 * (dx * dx + dy * dy));
}
