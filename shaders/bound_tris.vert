#version 450
// illum-bench raster, the geometry bound: every vertex at one point, so each triangle is
// fetched, transformed and assembled, then culled for its zero area (no pixel, no setup).
void main() {
  gl_Position = vec4(0.25, 0.25, 0.5, 1.0) + vec4(float(gl_VertexIndex & 1) * 1e-30);
}
