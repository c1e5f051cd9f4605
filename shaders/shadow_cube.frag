#version 450
#include "common.glsl"
// Distance to the light over the far distance, and its square (VSM moments).
layout(location = 0) in vec3 in_world;
layout(location = 0) out vec2 out_moments;
void main() {
  Light light = lights[push.light_index];
  float t = length(in_world - light.position_range.xyz) / light.shadow_params.x;
  // The second moment includes the in-texel slope (Donnelly & Lauritzen) against VSM acne.
  float dx = dFdx(t), dy = dFdy(t);
  out_moments = vec2(t, t * t + 0.25 * (dx * dx + dy * dy));
}
