#version 450
// debug.show of a 2-D float, single-channel or depth image (one layer, one mip in the view).
layout(set = 0, binding = 0) uniform sampler2D source;
#include "debug_show.glsl"

vec3 shown(vec2 uv) {
  ivec2 n = textureSize(source, 0);
  return from_float(texelFetch(source, min(ivec2(uv * vec2(n)), n - 1), 0));
}
