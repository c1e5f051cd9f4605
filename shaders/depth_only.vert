#version 450
// The depth pre-pass: forward.vert's position transform alone, on the packed position stream
// (GpuScene::positions). The shading or G-buffer pass that follows tests EQUAL against these
// depths, so the transform is forward.vert's, written the same way and `precise` there and
// here: no FMA contraction or reordering a compiler could choose differently per pipeline.
#include "common.glsl"

layout(location = 0) in vec3 in_position;
precise gl_Position;

void main() {
  vec4 world = push.model * vec4(in_position, 1.0);
  gl_Position = views[push.view].view_proj * world;
}
