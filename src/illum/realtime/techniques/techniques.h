// The declarations of the built-in techniques and globals, one function per file; only
// technique_registry.cpp lists them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "illum/core/auto_exposure_constants.h"
#include "illum/realtime/technique.h"

namespace illum::realtime {

TechniqueDecl lighting_globals();         // globals: lighting_globals.cpp
TechniqueDecl scene_draw_globals();       // globals: scene_draw_globals.cpp
TechniqueDecl forward_technique();        // forward.cpp
TechniqueDecl deferred_technique();       // deferred.cpp
TechniqueDecl visibility_technique();     // visibility.cpp
TechniqueDecl no_shadows_technique();     // shadow_maps.cpp
TechniqueDecl shadow_map_technique();     // shadow_maps.cpp (PCF)
TechniqueDecl vsm_technique();            // shadow_maps.cpp (variance shadow maps)
TechniqueDecl shadow_volume_technique();  // shadow_volumes.cpp
TechniqueDecl baked_technique();          // baked.cpp
TechniqueDecl ssao_technique();           // ssao.cpp
TechniqueDecl luminance_technique();      // luminance.cpp
TechniqueDecl bloom_technique();          // bloom.cpp
TechniqueDecl tonemap_technique();        // tonemap.cpp
TechniqueDecl debug_show_technique();     // debug_show.cpp
TechniqueDecl light_volume_technique();   // light_volume.cpp (the worked example)
TechniqueDecl rsm_technique();            // rsm.cpp (reflective shadow maps)
TechniqueDecl lpv_technique();            // lpv.cpp (light propagation volumes)
TechniqueDecl vpl_technique();            // vpl.cpp (virtual point lights from the RSMs)

// The integrals a light-propagation step needs (lpv.cpp, docs/realtime-lpv.md), for unit
// cells with the source's centre at the origin and the receiving neighbour along d = +z:
// over its far face (z = 3⁄2) the solid angle and ∫ω·d dω; over a side face (outward axis e,
// e.g. x = ½) the solid angle, ∫ω·e dω and ∫ω·d dω. Midpoint rule, samples² points a face.
struct LpvFaces {
  double far_solid_angle = 0.0, far_along = 0.0;
  double side_solid_angle = 0.0, side_across = 0.0, side_along = 0.0;
};
LpvFaces lpv_face_integrals(int samples);

// A directional light's reflective-shadow-map box (rsm.cpp) before snapping: the sphere around
// the camera's frustum (`inv_view_proj`, `eye`) from its near plane out to `distance` along its
// depth. Its radius depends on the frustum's shape only, so the box keeps its size as the
// camera turns.
struct RsmBox {
  vec3 centre{0.0f};
  float radius = 0.0f;
};
RsmBox rsm_directional_box(const mat4& inv_view_proj, const vec3& eye, float near_plane,
                           float distance);

// The visibility buffer's id packing (visibility.cpp): id = draw << triangle_bits | triangle.
struct VisibilityPacking {
  int triangle_bits = 1;
};
// Throws Error naming both counts when `draws` draws of up to `max_triangles` triangles do
// not fit 32 bits with the all-ones id kept out (a value no draw writes; empty pixels are
// told by their depth).
VisibilityPacking visibility_packing(size_t draws, size_t max_triangles);

// The "luminance" buffer (shaders/exposure.glsl): the histogram's bins, then the mean log2
// luminance between the percentiles and the exposure the rule gives.
inline constexpr uint32_t kExposureMeanOffset = exposure::kHistogramBins * sizeof(uint32_t);
inline constexpr uint32_t kExposureBufferBytes = kExposureMeanOffset + 2 * sizeof(float);

}  // namespace illum::realtime
