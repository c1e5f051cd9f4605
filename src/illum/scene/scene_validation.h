// The value rules for everything a scene format produces besides geometry — materials,
// lights, camera, environment, instance transforms — kept in one place so an OBJ/MTL, a glTF
// and an illum scene file meet the same limits. finalize_scene applies validate_scene_values
// to every loaded scene; loaders also call the small checks below on their raw values so the
// message can use the format's own names ("x.gltf: materials[2] 'Glass' emissiveFactor").
//
// Every check throws illum::Error "<where> ..." where `where` names the file and the element.
#pragma once

#include <cstddef>
#include <limits>
#include <string>

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum {

// Limits shared by every format (and by Params ranges in the scene-file reader).
inline constexpr float kMaxIor = 10.0f;      // dielectric index of refraction: [1, kMaxIor]
inline constexpr float kMaxExponent = 1e6f;  // Phong/Blinn exponent: [0, kMaxExponent]

// A number that must survive the cast to float: finite and within ±FLT_MAX (1e39 read as a
// double is fine, as a float it is infinity). Returns the float.
float checked_float(double value, const std::string& where);
// checked_float, and not negative: "<where> = v must not be negative".
float checked_non_negative(double value, const std::string& where);
// `value` finite and inside [lo, hi]: "<where> = v is outside [lo, hi]".
void check_in_range(double value, double lo, double hi, const std::string& where);
// Every component finite, ≥ 0 and ≤ `max`: "<where> is negative" / "... exceeds 1".
void check_color(const Color& c, const std::string& where,
                 float max = std::numeric_limits<float>::max());
// Every component finite.
void check_finite(const vec3& v, const std::string& where);
// Finite, affine (last row 0 0 0 1) and invertible with a finite inverse, so normals
// (inverse transpose) and directions stay finite: "<where> has a singular transform".
void check_transform(const mat4& m, const std::string& where);

// Reflectances (albedo, specular, transmittance) in [0, 1]; emission, eta, k ≥ 0; exponent in
// [0, kMaxExponent]; roughness, alpha and opacity in [0, 1]; ior in [1, kMaxIor]; normal_scale
// finite; texture ids kNoTexture or < texture_count.
void validate_material(const Material& m, const std::string& where, size_t texture_count);
// Finite position and direction (non-zero for spot and directional lights); intensity and
// irradiance finite and ≥ 0; spot cone half-angle in (0, π/2]; range finite and ≥ 0; an area
// light's instance < instance_count; an environment light needs `has_environment`.
void validate_light(const Light& l, const std::string& where, size_t instance_count,
                    bool has_environment);
// Finite position, look_at and up; fov_y in (0, π); look_at ≠ position; up not parallel to
// the view direction.
void validate_camera(const Camera& c, const std::string& where);
// scale finite and ≥ 0, rotation finite, constant colour finite and ≥ 0.
void validate_environment(const Environment& e, const std::string& where);

// All of the above over a scene, plus instance transforms (check_transform) and mesh ids.
// `origin` (the file) starts every message: "x.obj: material 'wood' albedo exceeds 1".
void validate_scene_values(const Scene& scene, const std::string& origin);

}  // namespace illum
