#version 450
// illum-bench raster: one triangle covering the whole target at depth 0.5 (the trivial
// full-screen pass whose time is a raster bound).
void main() {
  const vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.5, 1.0);
}
