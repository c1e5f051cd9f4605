// The declarations of the built-in techniques, one function per technique file; only
// technique_registry.cpp lists them.
#pragma once

#include <cstdint>

#include "illum/realtime/technique.h"

namespace illum::realtime {

TechniqueDecl lighting_technique();       // globals: lighting.cpp
TechniqueDecl forward_technique();        // forward.cpp
TechniqueDecl deferred_technique();       // deferred.cpp
TechniqueDecl no_shadows_technique();     // shadow_maps.cpp
TechniqueDecl shadow_map_technique();     // shadow_maps.cpp (PCF)
TechniqueDecl vsm_technique();            // shadow_maps.cpp (variance shadow maps)
TechniqueDecl shadow_volume_technique();  // shadow_volumes.cpp
TechniqueDecl baked_technique();          // baked.cpp
TechniqueDecl ssao_technique();           // ssao.cpp
TechniqueDecl luminance_technique();      // luminance.cpp
TechniqueDecl bloom_technique();          // bloom.cpp
TechniqueDecl tonemap_technique();        // tonemap.cpp

// 16×16 tiles of the log-average luminance (luminance.cpp); L_avg follows their partials.
uint32_t luminance_tiles(uint32_t width, uint32_t height);

}  // namespace illum::realtime
