#version 450
// illum-bench raster: a constant into 4 colour attachment(s), nothing else.
layout(location = 0) out vec4 color0;
layout(location = 1) out vec4 color1;
layout(location = 2) out vec4 color2;
layout(location = 3) out vec4 color3;
void main() {
  color0 = vec4(0.25, 0.5, 0.75, 1.0);
  color1 = vec4(0.25, 0.5, 0.75, 1.0);
  color2 = vec4(0.25, 0.5, 0.75, 1.0);
  color3 = vec4(0.25, 0.5, 0.75, 1.0);
}
