// Mesh clean-up shared by every loader (and by code that builds meshes itself): validation,
// degenerate-triangle removal, normal and tangent generation, transforms, and the final
// pass that turns a freshly parsed Scene into one the renderers can trust.
#pragma once

#include <cstddef>
#include <string>

#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum {

// Throws Error "<origin>: mesh 'x' has non-finite vertex N" for a NaN/Inf position, normal,
// tangent or uv; "<origin>: mesh 'x' triangle T uses vertex I, but it has only V vertices"
// for an out-of-range index; also for an index count that is not a multiple of 3, attribute
// arrays whose size differs from the positions', and a material id outside
// [0, material_count).
void validate_mesh(const Mesh& mesh, const std::string& origin, size_t material_count);

// Relative area below which a triangle counts as degenerate: area < kDegenerateRelArea·D²,
// D = the diagonal of the mesh's bounding box. Far below anything a modeller makes on
// purpose (a 1 km mesh keeps triangles of 1 mm²), well above float noise of exact zeros.
inline constexpr double kDegenerateRelArea = 1e-14;

// True when the triangle repeats an index, has two identical positions, or has
// (near-)zero area relative to `scale_sq` (= the squared diagonal of its mesh).
bool is_degenerate_triangle(const vec3& a, const vec3& b, const vec3& c, uint32_t ia, uint32_t ib,
                            uint32_t ic, double scale_sq);

// Removes degenerate triangles (see is_degenerate_triangle); returns how many. Vertices
// are kept (indices stay valid).
size_t drop_degenerate_triangles(Mesh& mesh);

// Fills normals that are absent (empty array) or zero with area-weighted averages of the
// adjacent triangles' normals. Vertices shared by index are smoothed; unshared vertices
// get their triangle's flat normal. Vertices no triangle uses get +y. Then normalizes all.
void compute_normals(Mesh& mesh);

// Per-vertex tangents from uv0 (MikkTSpace-like: per-triangle tangent and bitangent
// accumulated with corner-angle weights, Gram–Schmidt against the normal, handedness in
// w = ±1). Keeps loader-supplied tangents (re-orthonormalized). Clears them without uv0.
// Requires normals (call compute_normals first).
void compute_tangents(Mesh& mesh);

// Applies an object transform to positions, normals (inverse transpose) and tangents.
// A mirroring transform (negative determinant) reverses the triangle winding and the
// tangent handedness so front faces and normal maps stay consistent.
void transform_mesh(Mesh& mesh, const mat4& transform);

// Final pass over a parsed scene, in this order: validates every mesh (see validate_mesh)
// and every material, light, camera and instance transform (validate_scene_values in
// scene_validation.h); drops degenerate triangles with ONE warning (Scene::warnings)
// counting them; removes meshes left without triangles and their instances; fills normals
// and tangents; gives every emissive instance without one a kArea light; warns when the
// scene has no triangles. `origin` (the file) prefixes every message.
void finalize_scene(Scene& scene, const std::string& origin);

// Adds `message` to scene.warnings. Nothing is printed here: load_scene logs the warnings
// once the whole load has succeeded, so a failing load prints only its one error line.
void add_warning(Scene& scene, const std::string& message);

}  // namespace illum
