// debug.show (src/illum/realtime/techniques/debug_show.cpp): one texel of the shown image per
// output pixel (nearest, stretched to the frame), mapped to a display colour and written
// sRGB-encoded into the 8-bit output. Each debug_show*.comp declares `source` and defines
// shown(uv) for its kind of image.
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D ldr;
layout(push_constant) uniform Push {
  int mode;             // 0 colour, 1 grey (R), 2 depth linearised, 3 hashed uint, 4 raw depth
  int slice;            // 3-D images: the depth slice of the shown level
  float near_over_far;  // the camera's planes, for mode 2
  float unused;
} push;

vec3 from_float(vec4 v) {
  if (push.mode == 1 || push.mode == 4) return vec3(v.r);
  // Perspective depth d in [0, 1] (RH, zero-to-one): view depth ÷ far = r / (1 − d (1 − r)).
  if (push.mode == 2) return vec3(push.near_over_far / (1.0 - v.r * (1.0 - push.near_over_far)));
  return v.rgb;
}

// PCG hash: neighbouring ids get unrelated colours.
vec3 from_uint(uint v) {
  uint s = v * 747796405u + 2891336453u;
  uint w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
  w = (w >> 22u) ^ w;
  return vec3(w & 255u, (w >> 8u) & 255u, (w >> 16u) & 255u) / 255.0;
}

vec3 srgb_encode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

vec3 shown(vec2 uv);

void main() {
  ivec2 size = imageSize(ldr);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  imageStore(ldr, p, vec4(srgb_encode(shown((vec2(p) + 0.5) / vec2(size))), 1.0));
}
