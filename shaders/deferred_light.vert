#version 450
#include "common.glsl"
// Light volumes of the deferred path: a unit icosphere scaled to the light's radius, or (no
// radius, directional lights) a full-screen triangle at the far plane.
layout(location = 0) in vec3 in_position;
void main() {
  Light light = lights[push.light_index];
  if (push.mode == 1) {  // full screen
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
    return;
  }
  // The icosphere's faces are planar: circumscribe the sphere (1.26 > 1/cos of the
  // largest face-centre angle of an icosphere of level 1).
  vec3 world = light.position_range.xyz + in_position * light.position_range.w * 1.26;
  gl_Position = views[push.view].view_proj * vec4(world, 1.0);
}
