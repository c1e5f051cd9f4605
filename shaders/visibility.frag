#version 450
// The visibility buffer's id: draw index above the triangle index (realtime/techniques/
// visibility.cpp documents the packing; push.pad holds the triangle bits, push.view_index the
// draw). gl_PrimitiveID counts the triangles of this draw from its first index.
#include "common.glsl"

layout(location = 0) out uint out_id;

void main() {
  out_id = (uint(push.view_index) << uint(push.pad)) | uint(gl_PrimitiveID);
}
