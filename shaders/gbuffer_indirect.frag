#version 450
#define GBUFFER_INDIRECT
#include "gbuffer_pass.glsl"
