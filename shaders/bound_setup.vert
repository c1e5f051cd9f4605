#version 450
// illum-bench raster, the setup bound: triangle k is a small triangle in the corner of pixel
// k of a 1024×1024 target, away from the pixel's centre, so it passes clipping and culling,
// is set up and rasterized, and covers no sample: the cheapest triangle that reaches the
// rasterizer.
void main() {
  const int k = (gl_VertexIndex / 3) & 0xfffff;
  const int corner = gl_VertexIndex % 3;
  const vec2 pixel = vec2(k & 1023, k >> 10);
  const vec2 offset = vec2(0.1) + 0.3 * vec2(corner == 1, corner == 2);
  gl_Position = vec4((pixel + offset) / 512.0 - 1.0, 0.5, 1.0);
}
