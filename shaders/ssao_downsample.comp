#version 450
// SSAO plane pyramid, level m from level m − 1 (ssao_planes bound to that level's own view): one of
// every 2×2 texels, on a rotated grid — a copy, so a far tap still reads an exact plane.
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 4, rgba32ui) uniform writeonly uimage2D planes_out;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, imageSize(planes_out)))) return;
  ivec2 below = textureSize(ssao_planes, 0);
  imageStore(planes_out, texel, texelFetch(ssao_planes, ssao_child(texel, below), 0));
}
