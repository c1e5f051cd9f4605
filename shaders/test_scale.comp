#version 450
// Used by tests/gpu: data[i] = data[i] * scale + offset.
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Data { float data[]; };
layout(push_constant) uniform Push { float scale; float offset; uint count; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < count) data[i] = data[i] * scale + offset;
}
