#version 450
// illum-bench raster: a constant into 1 colour attachment(s), nothing else.
layout(location = 0) out vec4 color0;
void main() {
  color0 = vec4(0.25, 0.5, 0.75, 1.0);
}
