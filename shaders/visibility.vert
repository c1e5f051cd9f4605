#version 450
// The visibility buffer's one raster pass: positions only (the resolve reads the rest from
// the vertex buffer), the same transform as forward.vert so the depths agree.
#include "common.glsl"

layout(location = 0) in vec3 in_position;
// SceneDrawer draws a cluster with its first triangle in the mesh as the first instance.
layout(location = 0) flat out uint first_triangle;

void main() {
  vec4 world = push.model * vec4(in_position, 1.0);
  gl_Position = views[push.view].view_proj * world;
  first_triangle = uint(gl_InstanceIndex);
}
