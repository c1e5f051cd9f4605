#version 450
// debug.show of one depth slice of a 3-D float image (one mip in the view).
layout(set = 0, binding = 0) uniform sampler3D source;
#include "debug_show.glsl"

vec3 shown(vec2 uv) {
  ivec3 n = textureSize(source, 0);
  ivec2 t = min(ivec2(uv * vec2(n.xy)), n.xy - 1);
  return from_float(texelFetch(source, ivec3(t, clamp(push.slice, 0, n.z - 1)), 0));
}
