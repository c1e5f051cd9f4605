#include "illum/scene/scene_validation.h"

#include <cmath>

#include "illum/core/error.h"

namespace illum {

namespace {

std::string quoted_name(const std::string& name) {
  return name.empty() ? std::string() : fmt::format(" '{}'", name);
}

void check_texture(int id, size_t texture_count, const std::string& where) {
  if (id != kNoTexture && (id < 0 || static_cast<size_t>(id) >= texture_count))
    throw Error(fmt::format("{} refers to texture {}, but there are {} textures", where, id,
                            texture_count));
}

void check_non_negative(float v, const std::string& where) {
  if (!std::isfinite(v)) throw Error(fmt::format("{} = {} is not finite", where, v));
  if (v < 0.0f) throw Error(fmt::format("{} = {} must not be negative", where, v));
}

}  // namespace

float checked_float(double value, const std::string& where) {
  if (!std::isfinite(value) || std::abs(value) > std::numeric_limits<float>::max())
    throw Error(fmt::format("{} = {} is not a finite single-precision number", where, value));
  return static_cast<float>(value);
}

float checked_non_negative(double value, const std::string& where) {
  const float v = checked_float(value, where);
  if (v < 0.0f) throw Error(fmt::format("{} = {} must not be negative", where, value));
  return v;
}

void check_in_range(double value, double lo, double hi, const std::string& where) {
  if (!std::isfinite(value)) throw Error(fmt::format("{} = {} is not finite", where, value));
  if (value < lo || value > hi)
    throw Error(fmt::format("{} = {} is outside [{}, {}]", where, value, lo, hi));
}

void check_color(const Color& c, const std::string& where, float max) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(c[i]))
      throw Error(fmt::format("{} = ({}, {}, {}) is not finite", where, c.r, c.g, c.b));
    if (c[i] < 0.0f)
      throw Error(fmt::format("{} = ({}, {}, {}) is negative", where, c.r, c.g, c.b));
    if (c[i] > max)
      throw Error(fmt::format("{} = ({}, {}, {}) exceeds {}", where, c.r, c.g, c.b, max));
  }
}

void check_finite(const vec3& v, const std::string& where) {
  if (!is_finite(v))
    throw Error(fmt::format("{} = ({}, {}, {}) is not finite", where, v.x, v.y, v.z));
}

void check_transform(const mat4& m, const std::string& where) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) throw Error(fmt::format("{} has a non-finite transform", where));
    }
  }
  // Exact zeros and one: a matrix written by a tool or built from TRS keeps them exactly.
  if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
    throw Error(fmt::format("{} has a projective transform (last row must be 0 0 0 1)", where));
  const mat3 linear(m);
  const float det = glm::determinant(linear);
  const mat3 inverse = glm::inverse(linear);
  bool finite_inverse = det != 0.0f && std::isfinite(det);
  for (int c = 0; c < 3 && finite_inverse; ++c) finite_inverse = is_finite(inverse[c]);
  if (!finite_inverse)
    throw Error(fmt::format("{} has a singular transform (a zero scale or collapsed axes)", where));
}

void validate_material(const Material& m, const std::string& where, size_t texture_count) {
  check_color(m.albedo, where + " albedo", 1.0f);
  check_color(m.specular, where + " specular", 1.0f);
  check_color(m.transmittance, where + " transmittance", 1.0f);
  check_color(m.emission, where + " emission");
  check_color(m.eta, where + " eta");
  check_color(m.k, where + " k");
  check_in_range(m.exponent, 0.0, kMaxExponent, where + " exponent");
  check_in_range(m.roughness, 0.0, 1.0, where + " roughness");
  check_in_range(m.alpha, 0.0, 1.0, where + " alpha");
  check_in_range(m.ior, 1.0, kMaxIor, where + " ior");
  check_in_range(m.opacity, 0.0, 1.0, where + " opacity");
  if (!std::isfinite(m.normal_scale))
    throw Error(fmt::format("{} normal_scale = {} is not finite", where, m.normal_scale));
  check_texture(m.albedo_texture, texture_count, where + " albedo_texture");
  check_texture(m.roughness_texture, texture_count, where + " roughness_texture");
  check_texture(m.emission_texture, texture_count, where + " emission_texture");
  check_texture(m.normal_texture, texture_count, where + " normal_texture");
}

void validate_light(const Light& l, const std::string& where, size_t instance_count,
                    bool has_environment) {
  check_finite(l.position, where + " position");
  check_finite(l.direction, where + " direction");
  check_color(l.intensity, where + " intensity");
  check_color(l.irradiance, where + " irradiance");
  check_non_negative(l.range, where + " range");
  if ((l.type == LightType::kSpot || l.type == LightType::kDirectional) &&
      glm::length(l.direction) == 0.0f)
    throw Error(fmt::format("{} direction is a zero vector", where));
  if (l.type == LightType::kSpot && !(l.cone_half_angle > 0.0f && l.cone_half_angle <= 0.5f * kPi))
    throw Error(
        fmt::format("{} cone half-angle {} rad is outside (0, π/2]", where, l.cone_half_angle));
  if (l.type == LightType::kArea &&
      (l.instance < 0 || static_cast<size_t>(l.instance) >= instance_count))
    throw Error(fmt::format("{} refers to instance {}, but there are {} instances", where,
                            l.instance, instance_count));
  if (l.type == LightType::kEnvironment && !has_environment)
    throw Error(fmt::format("{} is an environment light, but the scene has no environment", where));
}

void validate_camera(const Camera& c, const std::string& where) {
  check_finite(c.position, where + " position");
  check_finite(c.look_at, where + " look_at");
  check_finite(c.up, where + " up");
  if (!(c.fov_y > 0.0f && c.fov_y < kPi))
    throw Error(fmt::format("{} vertical field of view {} rad is outside (0, π)", where, c.fov_y));
  const vec3 forward = c.look_at - c.position;
  if (glm::length(forward) == 0.0f || glm::length(glm::cross(forward, c.up)) == 0.0f)
    throw Error(fmt::format("{}: position, look_at and up do not span a view", where));
}

void validate_environment(const Environment& e, const std::string& where) {
  check_non_negative(e.scale, where + " scale");
  if (!std::isfinite(e.rotation_y))
    throw Error(fmt::format("{} rotation = {} is not finite", where, e.rotation_y));
  check_color(e.constant, where + " constant");
}

void validate_scene_values(const Scene& scene, const std::string& origin) {
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    validate_material(m, fmt::format("{}: material {}{}", origin, i, quoted_name(m.name)),
                      scene.textures.size());
  }
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const std::string where = fmt::format("{}: instance {}{}", origin, i, quoted_name(inst.name));
    if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= scene.meshes.size())
      throw Error(fmt::format("{} refers to mesh {}, but there are {} meshes", where, inst.mesh,
                              scene.meshes.size()));
    check_transform(inst.transform, where);
  }
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    validate_light(l, fmt::format("{}: light {}{}", origin, i, quoted_name(l.name)),
                   scene.instances.size(), scene.environment.has_value());
  }
  if (scene.camera) validate_camera(*scene.camera, origin + ": camera");
  if (scene.environment) validate_environment(*scene.environment, origin + ": environment");
  check_color(scene.settings.ambient, origin + ": settings ambient");
}

}  // namespace illum
