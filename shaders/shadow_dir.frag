#version 450
// VSM cascade of a directional light: orthographic depth is linear, so gl_FragCoord.z is the
// distance along the light; moments for VSM.
layout(location = 0) in vec3 in_world;
layout(location = 0) out vec2 out_moments;
void main() {
  float t = gl_FragCoord.z;
  float dx = dFdx(t), dy = dFdy(t);
  out_moments = vec2(t, t * t + 0.25 * (dx * dx + dy * dy));
}
