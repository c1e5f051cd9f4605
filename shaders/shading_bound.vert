#version 450
// The shading bound's full-screen triangle (realtime/measure/shading_bound.h) at the far plane:
// with the depth compare GREATER against the view's depth it passes exactly where a surface is
// (depth < 1), and early depth testing drops the background before it is shaded.
void main() {
  const vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
}
