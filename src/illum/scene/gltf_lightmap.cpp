#include "illum/scene/gltf_lightmap.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/hdr_encoding.h"
#include "illum/scene/mesh_processing.h"

namespace illum::detail {

namespace {

using nlohmann::json;

const json* child(const json* o, const char* key) {
  if (o == nullptr || !o->is_object()) return nullptr;
  const auto it = o->find(key);
  return it == o->end() ? nullptr : &*it;
}

// A string member, `fallback` when absent; nullopt when present and not a string.
std::optional<std::string> string_member(const json* o, const char* key, const char* fallback) {
  const json* v = child(o, key);
  if (v == nullptr) return std::string(fallback);
  if (!v->is_string()) return std::nullopt;
  return v->get<std::string>();
}

}  // namespace

std::optional<GltfLightmapReference> find_gltf_lightmap(const json& doc, const std::string& path,
                                                        Scene& scene) {
  const json* materials = child(&doc, "materials");
  if (materials == nullptr || !materials->is_array()) return std::nullopt;
  const json* textures = child(&doc, "textures");
  const size_t texture_count = textures != nullptr && textures->is_array() ? textures->size() : 0;
  const auto skip = [&](size_t material, const std::string& why) {
    add_warning(scene, fmt::format("{}: materials[{}] MSFT_lightmap {}: loaded without the "
                                   "light-map",
                                   path, material, why));
    return std::nullopt;
  };

  std::optional<GltfLightmapReference> found;
  for (size_t i = 0; i < materials->size(); ++i) {
    const json* ext = child(child(&(*materials)[i], "extensions"), "MSFT_lightmap");
    if (ext == nullptr) continue;
    const json* info = child(ext, "lightmapTexture");
    const json* index = child(info, "index");
    if (index == nullptr || !index->is_number_unsigned() || index->get<uint64_t>() >= texture_count)
      return skip(i, "names no texture of the file");
    // glTF's default texCoord is 0; illum's export always says 1.
    const json* coord = child(info, "texCoord");
    const int64_t tex_coord = coord == nullptr              ? 0
                              : coord->is_number_unsigned() ? coord->get<int64_t>()
                                                            : -1;
    if (tex_coord != 1)
      return skip(i, fmt::format("is on texCoord {}, not 1 (TEXCOORD_1, the light-map UVs)",
                                 coord == nullptr ? "0" : coord->dump()));
    const json* extras = child(ext, "extras");
    const std::optional<std::string> encoding = string_member(extras, "encoding", "");
    if (!encoding || *encoding != "RGBM")
      return skip(i, "has no extras.encoding \"RGBM\" (not an illum export)");
    const json* range = child(extras, "range");
    if (range == nullptr || !range->is_number() || !std::isfinite(range->get<double>()) ||
        !(range->get<double>() > 0.0) || !(range->get<double>() <= 3.4e38))
      return skip(i, "extras.range is not a positive finite number");
    const std::optional<std::string> tone = string_member(extras, "tone", "none");
    if (!tone || (*tone != "none" && *tone != "lrp97"))
      return skip(i, "extras.tone is neither \"none\" nor \"lrp97\"");
    GltfLightmapReference ref;
    ref.texture = static_cast<int>(index->get<uint64_t>());
    ref.lightmap.encoding = *encoding;
    ref.lightmap.range = static_cast<float>(range->get<double>());
    ref.lightmap.tone = *tone;
    ref.lightmap.basis = string_member(extras, "basis", "").value_or("").substr(0, 64);
    ref.lightmap.layer = string_member(extras, "layer", "").value_or("").substr(0, 200);
    if (!found) {
      found = std::move(ref);
    } else if (found->texture != ref.texture || found->lightmap.range != ref.lightmap.range ||
               found->lightmap.tone != ref.lightmap.tone) {
      return skip(
          i, fmt::format("names another light-map than materials before it "
                         "(texture {} range {}, not texture {} range {})",
                         ref.texture, ref.lightmap.range, found->texture, found->lightmap.range));
    }
  }
  return found;
}

Image decode_rgbm_lightmap(const Image& rgba, float range, const std::string& name) {
  if (rgba.channels() != 4)
    throw Error(
        fmt::format("{}: the RGBM light-map has {} channels, not 4 (RGB and the "
                    "multiplier)",
                    name, rgba.channels()));
  Image out(rgba.width(), rgba.height(), 3);
  for (int y = 0; y < rgba.height(); ++y)
    for (int x = 0; x < rgba.width(); ++x) {
      const float* p = rgba.pixel(x, y);
      std::array<uint8_t, 4> bytes{};
      for (size_t c = 0; c < 4; ++c)
        bytes[c] = static_cast<uint8_t>(std::lround(std::clamp(p[c], 0.0f, 1.0f) * 255.0f));
      out.set_rgb(x, y, decode_rgbm(bytes, range));
    }
  return out;
}

}  // namespace illum::detail
