#version 450
// illum-bench raster, the mixed bound: the first 3 × setup_triangles vertices are triangles
// set up and covering no sample (triangle k in a corner of pixel k, as bound_setup.vert), the
// rest the corners of full-target rectangles (4 each; the last one covers `partial` of the
// target's height), all at depth 0.5. The index buffer interleaves the two kinds.
layout(push_constant) uniform Mixed {
  ivec2 size;           // the target in pixels
  int setup_triangles;
  float partial;        // height fraction of the last rectangle
  int rectangles;
} mixed;
void main() {
  const int v = gl_VertexIndex;
  vec2 ndc;
  if (v < 3 * mixed.setup_triangles) {
    const int k = v / 3, corner = v % 3;
    const vec2 pixel = vec2(k % mixed.size.x, (k / mixed.size.x) % mixed.size.y);
    const vec2 offset = vec2(0.1) + 0.3 * vec2(corner == 1, corner == 2);
    ndc = (pixel + offset) / vec2(mixed.size) * 2.0 - 1.0;
  } else {
    const int u = v - 3 * mixed.setup_triangles, r = u / 4, corner = u % 4;
    const float height = r == mixed.rectangles - 1 ? mixed.partial : 1.0;
    ndc = vec2(corner & 1, (corner >> 1) * height) * 2.0 - 1.0;
  }
  gl_Position = vec4(ndc, 0.5, 1.0);
}
