#include "illum/realtime/baked_lightmap.h"

#include <algorithm>

#include "illum/core/error.h"

namespace illum::realtime {

Lightmap prepare_lightmap_display(Scene& scene, const baked::LightmapSet& set) {
  baked::apply_lightmap_set(scene, set);
  if (set.content == "all") {
    scene.lights.clear();
  } else {
    std::erase_if(scene.lights, [](const Light& light) {
      return light.type == LightType::kArea || light.type == LightType::kEnvironment;
    });
  }
  Lightmap lightmap;
  lightmap.kind = set.basis == "plain" ? LightmapKind::kPlain
                  : set.basis == "rnm" ? LightmapKind::kRnm
                  : set.basis == "sh"  ? LightmapKind::kShL1
                  : set.basis == "dominant"
                      ? LightmapKind::kDominant
                      : throw Error(fmt::format("light-map set '{}': unknown basis '{}'",
                                                set.folder, set.basis));
  lightmap.layers = set.layers;
  return lightmap;
}

}  // namespace illum::realtime
