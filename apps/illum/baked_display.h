// The bake folders `illum frame` and `illum view` show: `--baked DIR` (repeatable) reads each
// folder's manifest, tells its kind (baked_kind.h) and prepares the matching display of the
// `baked` add-on. Kinds, told by the manifest the folder holds:
//   lightmap.json  light-map (baked/lightmap_file.h)  → Renderer::set_lightmap
//   prt.json       PRT transfer (baked/prt_file.h)     → Renderer::set_prt
//   probes.json    irradiance probes (baked/probe_file.h) → Renderer::set_probe_volume, for
//                  the instances marked "dynamic": true (realtime/probe_volume.h)
// A new kind is one more entry in kBakedKinds (baked_kind.cpp) with its loader, and one
// more member here.
#pragma once

#include <string>
#include <vector>

#include "illum/realtime/baked_data.h"
#include "illum/realtime/renderer.h"
#include "illum/scene/scene.h"

namespace illum::cli {

struct BakedDisplay {
  realtime::Lightmap lightmap;   // kind kNone: no light-map folder
  realtime::PrtTransfer prt;     // empty: no PRT folder
  realtime::ProbeVolume probes;  // empty: no probe folder
  bool any() const {
    return lightmap.kind != realtime::LightmapKind::kNone || !prt.empty() || !probes.empty();
  }
  // Hands the data to a renderer built from the prepared scene (switches `baked` on).
  void show(realtime::Renderer& renderer) const;
};

// Loads `folders` (one of each kind at most), checks each was baked for `scene` (triangle
// count, then geometry hash: bake identity), puts its atlas on `scene` and removes the
// scene's lights the bake already holds (a light-map: as prepare_lightmap_display; PRT: all of
// them, the add-on's sun lights it). Throws Error — one line naming the folder — for a folder
// of no or an unknown kind, a malformed one, a second folder of one kind, a light-map and a
// PRT folder together (each puts its own atlas on uv1), a bake of another scene, or probes for
// a scene that marks no instance dynamic; `scene` is left as it was then. Probes combine with
// either of the others (they light the dynamic instances only). Without a light-map or PRT
// folder, a light-map the scene file carries (Scene::lightmap: illum's .glb export) is shown;
// refused with one line when it holds tone-mapped values or a mesh lacks its uv1.
BakedDisplay load_baked_display(Scene& scene, const std::vector<std::string>& folders);

}  // namespace illum::cli
