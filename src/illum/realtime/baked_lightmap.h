// Showing a baked light-map set (baked/lightmap_file.h, written by `illum bake`) in the
// real-time renderer.
#pragma once

#include "illum/baked/lightmap_file.h"
#include "illum/realtime/baked_data.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

// Prepares `scene` for a Renderer that shows `set`: puts the set's light-map coordinates on
// the meshes (baked::apply_lightmap_set) and removes the lights whose light the maps already
// hold, so nothing is counted twice — content "all": every light (the frame is emission +
// albedo × light-map); content "indirect": area and environment lights (their emitters
// still glow through their materials), keeping point, spot and directional lights for
// per-pixel shading with real-time shadows. Returns the layers as the renderer's Lightmap
// (pass it to Renderer::set_lightmap after constructing the renderer from `scene`).
// Throws Error when the set does not fit the scene.
Lightmap prepare_lightmap_display(Scene& scene, const baked::LightmapSet& set);

}  // namespace illum::realtime
