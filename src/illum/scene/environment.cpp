#include "illum/scene/environment.h"

#include <algorithm>
#include <cmath>

namespace illum {

namespace {
vec3 rotate_y(const vec3& d, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  // Right-handed rotation about +y: x' = c·x + s·z, z' = −s·x + c·z.
  return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}
}  // namespace

vec2 equirect_uv_from_direction(const vec3& dir, float rotation_y) {
  const vec3 d = glm::normalize(rotate_y(dir, -rotation_y));
  float u = 0.5f + std::atan2(d.x, -d.z) * (0.5f * kInvPi);
  if (u >= 1.0f) u -= 1.0f;  // atan2 = π exactly lands on 1; keep u in [0, 1)
  if (u < 0.0f) u += 1.0f;
  const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * kInvPi;
  return {u, v};
}

vec3 equirect_direction_from_uv(const vec2& uv, float rotation_y) {
  const float phi = (uv.x - 0.5f) * 2.0f * kPi;  // atan2(x, −z)
  const float theta = uv.y * kPi;                // polar angle from +y
  const float st = std::sin(theta);
  const vec3 local{st * std::sin(phi), std::cos(theta), -st * std::cos(phi)};
  return rotate_y(local, rotation_y);
}

Color environment_radiance(const Environment& env, const vec3& dir) {
  if (env.radiance.empty()) return env.scale * env.constant;
  const Image& img = env.radiance;
  const vec2 uv = equirect_uv_from_direction(dir, env.rotation_y);
  const int w = img.width(), h = img.height();
  // Continuous texel coordinates with texel centres at integers.
  const float x = uv.x * static_cast<float>(w) - 0.5f;
  const float y = uv.y * static_cast<float>(h) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  // Wrap horizontally (longitude is periodic); clamp vertically (the poles are edges).
  auto wrap_x = [w](int i) { return ((i % w) + w) % w; };
  auto clamp_y = [h](int j) { return std::clamp(j, 0, h - 1); };
  const int x0 = wrap_x(static_cast<int>(fx)), x1 = wrap_x(static_cast<int>(fx) + 1);
  const int y0 = clamp_y(static_cast<int>(fy)), y1 = clamp_y(static_cast<int>(fy) + 1);
  const Color top = (1.0f - tx) * img.rgb(x0, y0) + tx * img.rgb(x1, y0);
  const Color bottom = (1.0f - tx) * img.rgb(x0, y1) + tx * img.rgb(x1, y1);
  return env.scale * ((1.0f - ty) * top + ty * bottom);
}

}  // namespace illum
