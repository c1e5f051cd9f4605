// The folder `illum bake` writes and the real-time renderer reads: a baked light-map set.
//   lightmap.json   manifest: format "illum-lightmap" version 1, basis (plain|rnm|sh|dominant,
//                   or none: no layers, only extra maps), content (all|indirect; none with
//                   basis none), size, layer file names, atlas file, texel
//                   size, chart count, scene name and triangle count, scene_hash (the
//                   geometry_hash of the scene with the atlas applied, 16 hex digits:
//                   scene/geometry_hash.h), and the bake's own numbers (spp, seconds,
//                   rays, ...) under "bake"
//   atlas.bin       the atlas (atlas/atlas.h: save_atlas), needed to put uv1 on the scene again
//   layer0.exr ...  linear RGB layers (half floats), meaning per basis as in
//                   bake/lightmap_baker.h
//   preview.png     layer 0 tone-mapped (basis none: the first extra map), for people
//   ao.exr, obscurance.exr, obscurance_color.exr, bent_normal.exr
//                   optional extra maps (bake/lightmap_extras.h), linear half-float RGB,
//                   listed under "extras" as name → {"file", parameters}
// The folder is written next to its final place and renamed into it, so a failed or
// interrupted bake leaves no half-written set; an existing folder is replaced only when it
// holds an earlier set (a lightmap.json), never an unrelated folder.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/atlas/atlas.h"
#include "illum/core/image.h"

namespace illum::baked {

// An extra map (bake/lightmap_extras.h): ao, obscurance, obscurance_color (values in
// [0, 1], grey for the first two) or bent_normal (world-space unit xyz in [−1, 1]; 0 at
// texels no chart reaches). `params` holds the bake's parameters of the map (distance,
// d_max, rays, seed, ...) and is written beside "file" in the manifest.
struct LightmapExtra {
  std::string name;
  Image image;
  nlohmann::json params = nlohmann::json::object();
};
// The extra map names the folder format knows.
bool is_lightmap_extra_name(const std::string& name);

struct LightmapSet {
  atlas::Atlas atlas;
  std::string basis = "plain";  // plain | rnm | sh | dominant | none (extras only)
  std::string content = "all";  // all | indirect | none (with basis none)
  std::vector<Image> layers;    // 1 (plain), 3 (rnm, dominant), 4 (sh), 0 (none); atlas-sized RGB
  std::string scene;            // the scene's name, for the record and for messages
  size_t scene_triangles = 0;   // checked on load against the scene it is applied to
  // geometry_hash_hex of the baked scene after make_meshes_unique + apply_atlas; empty in a
  // folder written before scene hashes were recorded (then refused by apply_lightmap_set).
  std::string scene_hash;
  std::string folder;  // where load_lightmap_set read it from, for messages (empty: in memory)
  nlohmann::json bake = nlohmann::json::object();  // free-form numbers of the bake
  std::vector<LightmapExtra> extras;               // atlas-sized RGB, each name once
  // The extra called `name`, or nullptr.
  const LightmapExtra* extra(const std::string& name) const;
};

// Number of layers a basis has; throws Error for an unknown basis name.
int lightmap_layer_count(const std::string& basis);

// Throws Error unless `folder` can be written: its parent folder exists, and it does not
// exist or holds an earlier light-map set. save_lightmap_set checks this too; callers run it
// before long work so a bad path fails at once.
void check_lightmap_output(const std::filesystem::path& folder);
// Throws Error (one line) unless a bake of this `kind` ("light-map", "PRT", "probe") may
// write `folder`: its parent exists, and it does not exist or is an earlier bake folder of
// the kind (it holds `manifest_name`) holding only what a bake writes there: the manifest,
// preview.png and the files the manifest names. A file illum did not write is never
// deleted by replacing the folder.
void check_bake_output(const std::filesystem::path& folder, const std::string& manifest_name,
                       const std::string& kind);
// The absolute, normalised folder a bake writes (a trailing separator dropped).
std::filesystem::path bake_output_folder(const std::filesystem::path& folder);
// Writes a bake folder whole or not at all (light-map and PRT folders): `fill` writes the
// data files into a hidden sibling folder and returns the manifest, written last as
// `manifest_name`; then the finished folder is swapped in (an earlier one moved aside first,
// removed after). Any exception removes the sibling and leaves `folder` as it was.
void write_bake_folder(const std::filesystem::path& folder, const std::string& manifest_name,
                       const std::function<nlohmann::json(const std::filesystem::path&)>& fill);
void save_lightmap_set(const std::filesystem::path& folder, const LightmapSet& set);
// Throws Error naming the folder and the problem: missing folder or manifest, malformed
// JSON, wrong format/version, unknown basis or content, missing or mis-sized layers, a bad
// atlas file, an unknown or malformed extra, an extra map out of its range.
LightmapSet load_lightmap_set(const std::filesystem::path& folder);
// Throws Error (one line naming the folder and the extra maps it holds) when `set` has no
// layers (basis none), for readers that show or export the light: `use` says what for.
void require_lightmap_layers(const LightmapSet& set, const std::string& use);

// Puts the set's atlas on `scene` (make_meshes_unique + apply_atlas) after checking that the
// set was baked for this scene: the same triangle count, then the same geometry_hash once
// the atlas is applied. Throws Error (one line naming the folder, saying to bake again) and
// leaves `scene` unchanged when the set was baked for another scene or records no hash.
void apply_lightmap_set(Scene& scene, const LightmapSet& set);

}  // namespace illum::baked
