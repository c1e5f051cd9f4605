// Internal to the scene layer: the light-map of illum's own glTF export read back
// (MSFT_lightmap on TEXCOORD_1, decoding parameters in the extension's extras; the format:
// docs/lightmaps.md "Export to glTF", the writer: export/gltf_writer.h).
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "illum/core/image.h"
#include "illum/scene/scene.h"

namespace illum::detail {

struct GltfLightmapReference {
  int texture = -1;        // glTF textures[] index
  SceneLightmap lightmap;  // image not yet read
};

// The light-map the materials' MSFT_lightmap extensions name, when it is one illum shows:
// every material that has the extension names the same texture, on texCoord 1, with the same
// extras {"encoding": "RGBM", "range": M > 0, "tone": none | lrp97}. Any other use of the
// extension (another tool's light-map, other texture coordinates, mixed maps) is one warning
// on `scene`, which then loads without a light-map: the extension is optional, so the file
// stays readable. `doc` is the file's JSON, `path` names it in the warning.
std::optional<GltfLightmapReference> find_gltf_lightmap(const nlohmann::json& doc,
                                                        const std::string& path, Scene& scene);

// RGB values rgb·a·range per texel of the light-map's 8-bit RGBA image as decode_image
// returns it without the sRGB curve (each channel byte/255; illum's RGBM bytes are linear).
// Throws Error naming `name` unless the image has 4 channels.
Image decode_rgbm_lightmap(const Image& rgba, float range, const std::string& name);

}  // namespace illum::detail
