#version 450
// The visibility buffer's id: draw index above the triangle index (realtime/techniques/
// visibility.cpp documents the packing; push.mode holds the triangle bits, push.draw the
// draw). gl_PrimitiveID counts the triangles of this draw call from its first index; the
// draw call is a run of the mesh's clusters starting at triangle `first_triangle`.
#include "common.glsl"

layout(location = 0) flat in uint first_triangle;
layout(location = 0) out uint out_id;

void main() {
  out_id = (uint(push.draw) << uint(push.mode)) | (first_triangle + uint(gl_PrimitiveID));
}
