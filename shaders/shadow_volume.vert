#version 450
#include "common.glsl"
// Shadow-volume vertices are homogeneous: w = 0 puts the back cap at infinity (rendered with
// depth clamping so the far plane does not clip it).
layout(location = 0) in vec4 in_position;
void main() { gl_Position = views[push.view].view_proj * in_position; }
