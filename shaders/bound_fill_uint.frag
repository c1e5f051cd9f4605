#version 450
// illum-bench raster: a constant into one unsigned-integer attachment (the visibility ids).
layout(location = 0) out uvec4 id;
void main() {
  id = uvec4(12345u);
}
