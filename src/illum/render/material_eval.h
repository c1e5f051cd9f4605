// Texture-resolved material values at a surface point, shared by every offline renderer
// (and the photon tracer) so textures are read the same way everywhere.
#pragma once

#include "illum/core/color.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

// Colour texture lookup at `uv` (bilinear, wrapping); white when `texture` is kNoTexture
// or out of range.
Color texture_color(const Scene& scene, int texture, const vec2& uv);

// Diffuse albedo ρ × albedo texture at uv0.
Color material_albedo(const Scene& scene, const Material& material, const vec2& uv0);
// Emitted radiance L_e × emission texture at uv0 (W/(sr·m²)).
Color material_emission(const Scene& scene, const Material& material, const vec2& uv0);

// The material of a surface interaction (a default Lambert for out-of-range ids).
const Material& interaction_material(const Scene& scene, const SurfaceInteraction& si);

// Radiance emitted by the surface toward si.wo: emissive surfaces emit from the front face
// only (the side the geometric normal, i.e. the counter-clockwise winding, points to).
Color surface_emission(const Scene& scene, const SurfaceInteraction& si);

}  // namespace illum
