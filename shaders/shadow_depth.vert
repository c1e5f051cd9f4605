#version 450
#include "common.glsl"
// A depth-only shadow view (the PCF cascades): the depth buffer is the map, so the vertex
// carries nothing but its position (depth_only.frag is its empty fragment stage), and the
// draw pushes the view × model product (SceneView::clip_from_world): one transform a vertex.
layout(location = 0) in vec3 in_position;
void main() { gl_Position = push.model * vec4(in_position, 1.0); }
