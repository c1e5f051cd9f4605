#version 450
#include "shadow_set.glsl"
layout(location = 0) in vec3 in_position;
layout(location = 0) out vec3 out_world;
void main() {
  vec4 world = push.model * vec4(in_position, 1.0);
  out_world = world.xyz;
  gl_Position = views[push.view].view_proj * world;
}
