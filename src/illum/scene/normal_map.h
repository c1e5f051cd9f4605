// Tangent-space normal maps, read one way by every offline consumer (the ray tracer's
// shading normal, the PRT baker's perturbed normals): glTF convention, linear texel in
// [0,1] → [−1,1], x and y scaled by the material's normal_scale, +x along the tangent, +y
// along the bitangent (the direction of increasing v), +z along the surface normal.
#pragma once

#include "illum/core/image.h"
#include "illum/scene/scene.h"

namespace illum {

// The material's normal map, or nullptr when it has none (no texture, an index out of
// range, an empty image).
const Image* normal_map_of(const Scene& scene, const Material& material);

// The unit normal `map` gives at uv0 (bilinear, wrapping) in the frame (tangent, bitangent,
// normal), which the caller makes orthonormal. False, `out` untouched, when the mapped
// vector has no length (a texel of (0.5, 0.5, 0.5)) or is not finite.
bool mapped_normal(const Image& map, float normal_scale, const vec2& uv0, const vec3& tangent,
                   const vec3& bitangent, const vec3& normal, vec3* out);

}  // namespace illum
