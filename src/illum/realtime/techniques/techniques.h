// The declarations of the built-in techniques and globals, one function per file; only
// technique_registry.cpp lists them.
#pragma once

#include <cstddef>
#include <cstdint>

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

// The visibility buffer's id packing (visibility.cpp): id = draw << triangle_bits | triangle.
struct VisibilityPacking {
  int triangle_bits = 1;
};
// Throws Error naming both counts when `draws` draws of up to `max_triangles` triangles do
// not fit 32 bits with the all-ones id kept out (a value no draw writes; empty pixels are
// told by their depth).
VisibilityPacking visibility_packing(size_t draws, size_t max_triangles);

// 16×16 tiles of the log-average luminance (luminance.cpp); L_avg follows their partials.
uint32_t luminance_tiles(uint32_t width, uint32_t height);

}  // namespace illum::realtime
