#version 450
// Test kernel (tests/realtime/frame_graph_gpu_test): a 3-D image holding a linear function
// of the texel index, f = c.x i + c.y j + c.z k + c.w.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 0, rgba16f) uniform writeonly image3D volume;
layout(push_constant) uniform Push { vec4 c; } push;

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, imageSize(volume)))) return;
  imageStore(volume, p, vec4(dot(push.c.xyz, vec3(p)) + push.c.w));
}
