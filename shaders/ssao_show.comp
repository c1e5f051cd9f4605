#version 450
// -p ssao.output=ao: the AO buffer itself into the HDR target (grey), for inspection and the
// comparison with the offline `ao` integrator.
layout(local_size_x = 8, local_size_y = 8) in;
#include "ssao_set.glsl"
layout(set = 2, binding = 5, rgba16f) uniform writeonly image2D hdr_out;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.extent.xy)))) return;
  float a = texelFetch(ssao_source, pixel, 0).r;
  imageStore(hdr_out, pixel, vec4(a, a, a, 1.0));
}
