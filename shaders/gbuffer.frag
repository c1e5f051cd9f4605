#version 450
#include "gbuffer_pass.glsl"
