// Math types: glm (GLSL-compatible) vectors and matrices, plus the small helpers the
// renderers share. Right-handed, +y up, metres.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace illum {

using glm::ivec2;
using glm::mat3;
using glm::mat4;
using glm::uvec3;
using glm::vec2;
using glm::vec3;
using glm::vec4;

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInf = std::numeric_limits<float>::infinity();

struct Ray {
  vec3 origin{0.0f};
  vec3 direction{0.0f, 0.0f, 1.0f};  // need not be normalized for queries; integrators keep it unit
  float tmin = 0.0f;
  float tmax = kInf;
};

// Axis-aligned bounding box; empty when min > max.
struct Bounds3 {
  vec3 min{kInf};
  vec3 max{-kInf};
  void extend(const vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Bounds3& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  vec3 extent() const { return empty() ? vec3(0.0f) : max - min; }
  vec3 center() const { return 0.5f * (min + max); }
  float diagonal() const { return glm::length(extent()); }
};

// Orthonormal frame around a unit normal; local z is the normal.
struct Frame {
  vec3 t, b, n;
  Frame() : t(1, 0, 0), b(0, 1, 0), n(0, 0, 1) {}
  Frame(const vec3& tangent, const vec3& bitangent, const vec3& normal)
      : t(tangent), b(bitangent), n(normal) {}
  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited": branch-free, no
  // singularity at n = ±z.
  static Frame from_normal(const vec3& normal) {
    const float sign = std::copysign(1.0f, normal.z);
    const float a = -1.0f / (sign + normal.z);
    const float c = normal.x * normal.y * a;
    return Frame(vec3(1.0f + sign * normal.x * normal.x * a, sign * c, -sign * normal.x),
                 vec3(c, sign + normal.y * normal.y * a, -normal.y), normal);
  }
  vec3 to_local(const vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  vec3 to_world(const vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

inline bool is_finite(const vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline float max_component(const vec3& v) {
  return std::max(v.x, std::max(v.y, v.z));
}
inline float radians(float degrees) {
  return degrees * (kPi / 180.0f);
}

// Offsets a ray origin along the geometric normal to escape self-intersection; scaled by
// the magnitude of the point so it works in millimetre and kilometre scenes alike.
inline vec3 offset_ray_origin(const vec3& p, const vec3& ng, const vec3& dir) {
  const float scale = 1e-4f * std::max(1.0f, max_component(glm::abs(p)));
  const vec3 n = glm::dot(ng, dir) >= 0.0f ? ng : -ng;
  return p + scale * n;
}

}  // namespace illum
