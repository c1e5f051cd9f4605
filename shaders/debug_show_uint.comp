#version 450
// debug.show of a 2-D unsigned-integer image (the visibility buffer's ids): hashed colours.
layout(set = 0, binding = 0) uniform usampler2D source;
#include "debug_show.glsl"

vec3 shown(vec2 uv) {
  ivec2 n = textureSize(source, 0);
  return from_uint(texelFetch(source, min(ivec2(uv * vec2(n)), n - 1), 0).r);
}
