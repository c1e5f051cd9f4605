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
