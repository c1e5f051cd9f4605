#version 450
// illum-bench raster, the mixed and setup bounds: the first `setup_vertices` vertices make
// triangles set up and covering no sample — patches of cells × cells cells of shared
// vertices, patch k inside a corner of pixel k or of a pixel scattered by k, away from its centre (the sample) — the rest
// the corners of full-target rectangles (4 each; the last one covers `partial` of the
// target's height), all at depth 0.5. The index buffer (bench/suites/raster_passes.cpp) interleaves
// the two kinds.
layout(push_constant) uniform Mixed {
  ivec2 size;  // the target in pixels
  int setup_vertices;
  float partial;  // height fraction of the last rectangle
  int rectangles;
  int cells;   // cells per side of a patch
  int spread;  // 0: patch k in pixel k (row by row), 1: in a pixel scattered over the target,
               // 2: covering — each cell 2 × 1 pixels, each triangle holding one sample
} mixed;
void main() {
  const int v = gl_VertexIndex;
  vec2 ndc;
  if (v < mixed.setup_vertices) {
    const int side = mixed.cells + 1;
    const int k = v / (side * side), local = v % (side * side);
    if (mixed.spread == 2) {
      // Patches tile the target row by row (wrapping onto it again past its last row): a
      // cell's two triangles split it along the diagonal from (2, 0) to (0, 1), one pixel
      // centre on each side of it, none on an edge.
      const int across = max(1, mixed.size.x / (2 * mixed.cells));
      const int rows = max(1, mixed.size.y / mixed.cells);
      const ivec2 origin = ivec2(k % across * 2 * mixed.cells, k / across % rows * mixed.cells);
      const vec2 at = vec2(origin) + vec2(2 * (local % side), local / side);
      gl_Position = vec4(at / vec2(mixed.size) * 2.0 - 1.0, 0.5, 1.0);
      return;
    }
    const uint pixels = uint(mixed.size.x * mixed.size.y);
    // Knuth's multiplicative hash scatters consecutive patches over the whole target.
    const uint at = mixed.spread == 1 ? (uint(k) * 2654435761u) % pixels : uint(k) % pixels;
    const vec2 pixel = vec2(at % uint(mixed.size.x), at / uint(mixed.size.x));
    // The patch spans [0.1, 0.4] of its pixel: no sample (the centre) inside or on an edge.
    const vec2 offset = vec2(0.1) + 0.3 * vec2(local % side, local / side) / float(mixed.cells);
    ndc = (pixel + offset) / vec2(mixed.size) * 2.0 - 1.0;
  } else {
    const int u = v - mixed.setup_vertices, r = u / 4, corner = u % 4;
    const float height = r == mixed.rectangles - 1 ? mixed.partial : 1.0;
    ndc = vec2(corner & 1, (corner >> 1) * height) * 2.0 - 1.0;
  }
  gl_Position = vec4(ndc, 0.5, 1.0);
}
