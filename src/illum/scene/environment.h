// Equirectangular (latitude–longitude) environment maps: direction ↔ texture coordinates
// and radiance lookup.
//
// Mapping (world space, right-handed, +y up), for a unit direction d and before rotation:
//   u = 0.5 + atan2(d.x, −d.z) / (2π)   ∈ [0, 1): u = 0.5 looks down −z, u = 0.75 toward +x,
//                                         u = 0 / 1 toward +z (the seam is behind the viewer);
//                                         seen from inside, the panorama is not mirrored.
//   v = acos(d.y) / π                     ∈ [0, 1]: v = 0 is the zenith (+y, the top row),
//                                         v = 1 the nadir.
// Image pixel (x, y) covers u ∈ [x/w, (x+1)/w), v ∈ [y/h, (y+1)/h); texel centres sit at
// half-integers. Environment::rotation_y = θ turns the map by θ about +y (right-handed:
// counter-clockwise seen from above), so a world direction d reads the map at R_y(−θ)·d.
#pragma once

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum {

// Unit direction → (u, v) per the mapping above, with the map rotated by rotation_y.
vec2 equirect_uv_from_direction(const vec3& dir, float rotation_y = 0.0f);
// (u, v) → unit world direction; the inverse of equirect_uv_from_direction.
vec3 equirect_direction_from_uv(const vec2& uv, float rotation_y = 0.0f);

// Radiance arriving from direction `dir` (pointing away from the scene, toward the sky):
// scale × (bilinear map lookup, wrapping in u and clamping in v), or scale × constant
// when the map is empty. `dir` need not be normalized.
Color environment_radiance(const Environment& env, const vec3& dir);

}  // namespace illum
