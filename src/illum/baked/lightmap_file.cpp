#include "illum/baked/lightmap_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include <fmt/format.h>

#include "illum/baked/manifest_fields.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"
#include "illum/core/interrupt.h"
#include "illum/core/json_input.h"
#include "illum/core/tonemap.h"
#include "illum/scene/geometry_hash.h"

namespace illum::baked {

namespace fs = std::filesystem;

namespace {

constexpr const char* kManifest = "lightmap.json";
constexpr const char* kAtlasFile = "atlas.bin";
constexpr int kVersion = 1;

std::string layer_name(size_t i) {
  return fmt::format("layer{}.exr", i);
}

// Preview exposure: key 0.18 over the log-average luminance of the lit texels, so a dim
// indirect-only map and a bright direct map are both readable. "Lit" is above 1e-4 of the
// brightest texel: black texels (unused atlas space, texels inside geometry) are left out,
// and so are the near-black ones a denoiser leaves there, which would otherwise pull the
// average down and the preview's exposure up.
Image preview_of(const Image& layer) {
  float brightest = 0.0f;
  for (int y = 0; y < layer.height(); ++y)
    for (int x = 0; x < layer.width(); ++x)
      brightest = std::max(brightest, luminance(layer.rgb(x, y)));
  double log_sum = 0.0;
  size_t n = 0;
  for (int y = 0; y < layer.height(); ++y)
    for (int x = 0; x < layer.width(); ++x) {
      const float l = luminance(layer.rgb(x, y));
      if (l > 1e-4f * brightest) {
        log_sum += std::log(double(l));
        ++n;
      }
    }
  const float average = n ? float(std::exp(log_sum / double(n))) : 1.0f;
  return tone_mapped(layer, ToneMapper::kAces, 0.18f / average);
}

constexpr const char* kExtraNames[] = {"ao", "obscurance", "obscurance_color", "bent_normal"};

std::string extra_file_name(const std::string& name) {
  return name + ".exr";
}

// Half floats carry 11 significant bits: a unit vector's length comes back within a few
// 2^-11 (three components rounded by at most 2^-12 each, relative).
constexpr float kUnitLengthTolerance = 4.0f / 2048.0f;

// Throws Error naming `where` unless the texels of `image` lie in the range of extra `name`.
void check_extra_values(const std::string& where, const std::string& name, const Image& image) {
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Color c = image.rgb(x, y);
      if (name == "bent_normal") {
        const float len = glm::length(vec3(c));
        if (len != 0.0f && std::abs(len - 1.0f) > kUnitLengthTolerance)
          throw Error(
              fmt::format("{}: texel ({}, {}) has length {}, but bent normals are unit "
                          "vectors (or 0 outside the charts)",
                          where, x, y, len));
      } else {
        for (int k = 0; k < 3; ++k)
          if (!(c[k] >= 0.0f && c[k] <= 1.0f))
            throw Error(
                fmt::format("{}: texel ({}, {}) holds {}, outside [0, 1]", where, x, y, c[k]));
        if (name != "obscurance_color" && (c[0] != c[1] || c[1] != c[2]))
          throw Error(fmt::format("{}: texel ({}, {}) is not grey ({}, {}, {})", where, x, y, c[0],
                                  c[1], c[2]));
      }
    }
}

}  // namespace

bool is_lightmap_extra_name(const std::string& name) {
  for (const char* n : kExtraNames)
    if (name == n) return true;
  return false;
}

const LightmapExtra* LightmapSet::extra(const std::string& name) const {
  for (const LightmapExtra& e : extras)
    if (e.name == name) return &e;
  return nullptr;
}

namespace {

// The folder a path names, absolute, without a trailing separator ("out/" is "out").
}  // namespace

fs::path bake_output_folder(const fs::path& folder) {
  fs::path target = fs::absolute(folder).lexically_normal();
  return target.has_filename() ? target : target.parent_path();
}

namespace {

// Every string in a manifest that could name a file of its folder.
void collect_strings(const nlohmann::json& j, std::vector<std::string>* out) {
  if (j.is_string()) out->push_back(j.get<std::string>());
  if (j.is_array() || j.is_object())
    for (const auto& item : j) collect_strings(item, out);
}

}  // namespace

void check_bake_output(const fs::path& folder, const std::string& manifest_name,
                       const std::string& kind) {
  const fs::path target = bake_output_folder(folder);
  std::error_code ec;
  if (!fs::is_directory(target.parent_path(), ec))
    throw Error(fmt::format("{}: folder '{}' does not exist", folder.string(),
                            target.parent_path().string()));
  if (!fs::exists(target, ec)) return;
  if (!fs::is_directory(target, ec) || !fs::exists(target / manifest_name, ec))
    throw Error(fmt::format("{}: exists and is not a {} folder (no {}); refusing to replace it",
                            folder.string(), kind, manifest_name));
  std::vector<std::string> own = {manifest_name, "preview.png"};
  try {
    std::ifstream in(target / manifest_name);
    collect_strings(nlohmann::json::parse(in), &own);
  } catch (const std::exception&) {
    // An unreadable manifest names no file: only the manifest and preview count as own.
  }
  for (const fs::directory_entry& entry : fs::directory_iterator(target, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file(ec) || std::find(own.begin(), own.end(), name) == own.end())
      throw Error(
          fmt::format("{}: holds '{}', which no {} bake wrote; refusing to replace the "
                      "folder (move it away first)",
                      folder.string(), name, kind));
  }
}

void write_bake_folder(const fs::path& folder, const std::string& manifest_name,
                       const std::function<nlohmann::json(const fs::path&)>& fill) {
  const fs::path target = bake_output_folder(folder);
  const fs::path parent = target.parent_path();
  std::random_device random;
  const fs::path staging =
      parent / fmt::format(".{}.partial-{:08x}", target.filename().string(), random());
  fs::create_directories(staging);
  const StagingPath staged(staging.string());  // a second Ctrl-C removes it
  try {
    const nlohmann::json manifest = fill(staging);
    // Checked to the last byte (core/file_write.h): a full disk is an error, not a torn
    // manifest in a folder that then looks finished.
    write_file_atomically((staging / manifest_name).string(), manifest.dump(2) + "\n");
    fs::path old;
    if (fs::exists(target)) {
      old = parent / fmt::format(".{}.old-{:08x}", target.filename().string(), random());
      fs::rename(target, old);
    }
    fs::rename(staging, target);
    if (!old.empty()) fs::remove_all(old);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
}

void check_lightmap_output(const fs::path& folder) {
  check_bake_output(folder, kManifest, "light-map");
}

int lightmap_layer_count(const std::string& basis) {
  if (basis == "plain") return 1;
  if (basis == "rnm") return 3;
  if (basis == "sh") return 4;
  if (basis == "dominant") return 3;  // ambient, directional colour, direction (bake/)
  if (basis == "none") return 0;      // only extra maps (`illum bake --basis none`)
  throw Error(
      fmt::format("unknown light-map basis '{}' (plain, rnm, sh, dominant or none)", basis));
}

void save_lightmap_set(const fs::path& folder, const LightmapSet& set) {
  const size_t expected = size_t(lightmap_layer_count(set.basis));
  if (set.layers.size() != expected)
    throw Error(fmt::format("light-map set: basis '{}' needs {} layers, got {}", set.basis,
                            expected, set.layers.size()));
  if (set.basis == "none" && set.extras.empty())
    throw Error("light-map set: basis 'none' holds only extra maps, and none is given");
  for (size_t i = 0; i < set.extras.size(); ++i) {
    const LightmapExtra& e = set.extras[i];
    if (!is_lightmap_extra_name(e.name))
      throw Error(fmt::format("light-map set: unknown extra map '{}'", e.name));
    if (set.extra(e.name) != &e)
      throw Error(fmt::format("light-map set: extra map '{}' given twice", e.name));
    if (e.image.width() != set.atlas.width || e.image.height() != set.atlas.height ||
        e.image.channels() != 3)
      throw Error(fmt::format("light-map set: extra map '{}' is {}x{}x{}, not {}x{} RGB", e.name,
                              e.image.width(), e.image.height(), e.image.channels(),
                              set.atlas.width, set.atlas.height));
    if (!e.params.is_object())
      throw Error(
          fmt::format("light-map set: extra map '{}' parameters must be an object", e.name));
    check_extra_values(fmt::format("light-map set: extra map '{}'", e.name), e.name, e.image);
  }
  check_lightmap_output(folder);
  write_bake_folder(folder, kManifest, [&](const fs::path& staging) {
    nlohmann::json layers = nlohmann::json::array();
    ImageWriteOptions exr;
    exr.exr_half = true;
    for (size_t i = 0; i < set.layers.size(); ++i) {
      write_image((staging / layer_name(i)).string(), set.layers[i], exr);
      layers.push_back(layer_name(i));
    }
    // Without layers the first extra map (values in [0, 1] or unit vectors) is the preview.
    write_image((staging / "preview.png").string(),
                set.layers.empty() ? set.extras[0].image : preview_of(set.layers[0]));
    atlas::save_atlas(set.atlas, staging / kAtlasFile);
    nlohmann::json extras = nlohmann::json::object();
    for (const LightmapExtra& e : set.extras) {
      write_image((staging / extra_file_name(e.name)).string(), e.image, exr);
      nlohmann::json entry = e.params;
      entry["file"] = extra_file_name(e.name);
      extras[e.name] = entry;
    }
    nlohmann::json manifest = {{"format", "illum-lightmap"},
                               {"version", kVersion},
                               {"basis", set.basis},
                               {"content", set.content},
                               {"width", set.atlas.width},
                               {"height", set.atlas.height},
                               {"layers", layers},
                               {"atlas", kAtlasFile},
                               {"texel_size", set.atlas.texel_size},
                               {"charts", set.atlas.chart_count},
                               {"scene", set.scene},
                               {"scene_triangles", set.scene_triangles},
                               {"bake", set.bake}};
    if (!set.scene_hash.empty()) manifest["scene_hash"] = set.scene_hash;
    if (!set.extras.empty()) manifest["extras"] = extras;
    return manifest;
  });
}

LightmapSet load_lightmap_set(const fs::path& folder) {
  const std::string where = folder.string();
  std::error_code ec;  // an unreadable path is "does not exist", not a filesystem_error
  if (!fs::is_directory(folder, ec))
    throw Error(fmt::format("light-map folder '{}' does not exist", where));
  const std::string manifest_where = fmt::format("{}/{}", where, kManifest);
  if (!fs::is_regular_file(folder / kManifest, ec))
    throw Error(fmt::format("{}: no {} (not a light-map folder)", where, kManifest));
  // Bounded nesting and every parser exception as an Error, like any JSON a user hands in
  // (core/json_input.h): the manifest's "bake" object is copied, which recurses.
  const nlohmann::json json = read_json_file(manifest_where);
  const ManifestFields manifest(json, manifest_where);
  LightmapSet set;
  set.folder = where;
  manifest.expect_format("illum-lightmap", kVersion);
  set.basis = manifest.one_of("basis", {"plain", "rnm", "sh", "dominant", "none"});
  const int expected = lightmap_layer_count(set.basis);
  // Content describes the layers: basis none (extra maps only) has none.
  set.content = set.basis == "none" ? manifest.one_of("content", {"none"})
                                    : manifest.one_of("content", {"all", "indirect"});
  set.scene = manifest.string("scene");
  set.scene_triangles = manifest.integer("scene_triangles", 0, kMaxManifestTriangles);
  // Optional here so that an old folder loads and apply_lightmap_set can say what to do.
  if (manifest.has("scene_hash")) set.scene_hash = manifest.scene_hash("scene_hash");
  if (manifest.has("bake")) set.bake = manifest.free_object("bake");
  const nlohmann::json& layers = manifest.at("layers");
  if (!layers.is_array())
    manifest.fail(fmt::format("'layers' must be a list of file names, not {}",
                              ManifestFields::shown(layers)));
  if (static_cast<int>(layers.size()) != expected)
    manifest.fail(fmt::format("'layers' lists {}, but basis '{}' needs {}", layers.size(),
                              set.basis, expected));
  std::vector<std::string> names;
  for (const nlohmann::json& layer : layers) names.push_back(manifest.file_name("layers", layer));
  // Types and ranges first, so a wrong one is named as such rather than as a mismatch.
  set.atlas = read_manifest_atlas(manifest, folder);
  for (const std::string& name : names) {
    // The reader refuses malformed, oversized and non-finite (NaN/Inf) files, naming them.
    Image layer = read_image((folder / name).string(), false);
    if (layer.width() != set.atlas.width || layer.height() != set.atlas.height)
      throw Error(fmt::format("{}/{}: {}x{}, but the atlas is {}x{}", where, name, layer.width(),
                              layer.height(), set.atlas.width, set.atlas.height));
    if (layer.channels() != 3)
      throw Error(fmt::format("{}/{}: {} channels, but light-map layers are RGB", where, name,
                              layer.channels()));
    set.layers.push_back(std::move(layer));
  }
  if (manifest.json().contains("extras")) {
    const nlohmann::json& extras = manifest.at("extras");
    if (!extras.is_object())
      manifest.fail(
          fmt::format("'extras' must be an object of extra map name → {{\"file\": ...}}, "
                      "not {}",
                      ManifestFields::shown(extras)));
    for (const auto& [name, entry] : extras.items()) {
      if (!is_lightmap_extra_name(name))
        manifest.fail(
            fmt::format("unknown extra map '{}' (ao, obscurance, obscurance_color, bent_normal)",
                        name.substr(0, 40)));
      if (!entry.is_object() || !entry.contains("file"))
        manifest.fail(fmt::format("extra map '{}' must be an object with a \"file\"", name));
      const std::string file = manifest.file_name("extras", entry.at("file"));
      const std::string file_where = fmt::format("{}/{}", where, file);
      Image image = read_image((folder / file).string(), false);
      if (image.width() != set.atlas.width || image.height() != set.atlas.height)
        throw Error(fmt::format("{}: {}x{}, but the atlas is {}x{}", file_where, image.width(),
                                image.height(), set.atlas.width, set.atlas.height));
      if (image.channels() != 3)
        throw Error(
            fmt::format("{}: {} channels, but extra maps are RGB", file_where, image.channels()));
      check_extra_values(file_where, name, image);
      LightmapExtra extra;
      extra.name = name;
      extra.image = std::move(image);
      extra.params = entry;
      extra.params.erase("file");
      set.extras.push_back(std::move(extra));
    }
  }
  if (set.basis == "none" && set.extras.empty())
    manifest.fail("basis 'none' holds only extra maps, but 'extras' lists none");
  return set;
}

void require_lightmap_layers(const LightmapSet& set, const std::string& use) {
  if (!set.layers.empty()) return;
  std::string names;
  for (const LightmapExtra& e : set.extras) names += (names.empty() ? "" : ", ") + e.name;
  throw Error(fmt::format(
      "{}: holds only extra maps ({}; baked with --basis none), no light-map layers to {}; "
      "bake it with --basis plain, rnm, sh or dominant",
      set.folder.empty() ? "light-map set" : set.folder, names, use));
}

void apply_lightmap_set(Scene& scene, const LightmapSet& set) {
  const std::string where = set.folder.empty() ? "light-map set" : set.folder;
  // Both hashes in every refusal (bake identity): with another triangle count the atlas
  // cannot be applied, so the scene's is its hash as loaded.
  if (scene.triangle_count() != set.scene_triangles)
    throw Error(fmt::format(
        "{}: baked for '{}' ({} triangles, scene hash {}), which does not fit scene '{}' ({} "
        "triangles, scene hash {} without the atlas); bake it again for this scene",
        where, set.scene, set.scene_triangles, set.scene_hash.empty() ? "none" : set.scene_hash,
        scene.name, scene.triangle_count(), geometry_hash_hex(scene)));
  if (set.scene_hash.empty())
    throw Error(fmt::format(
        "{}: records no scene hash (baked by an earlier illum), so it cannot be checked "
        "against scene '{}'; bake it again",
        where, scene.name));
  // A refused set leaves the caller's scene as it was: the atlas changes only meshes and
  // instances, so those are kept (not the textures: a copy of the whole scene could be large).
  std::vector<Mesh> meshes = scene.meshes;
  std::vector<Instance> instances = scene.instances;
  try {
    atlas::make_meshes_unique(scene);
    atlas::apply_atlas(scene, set.atlas);
    const std::string hash = geometry_hash_hex(scene);
    if (hash != set.scene_hash)
      throw Error(fmt::format(
          "{}: baked for another scene than '{}' (scene hash {} recorded, {} here: other "
          "positions, normals, transforms or atlas); bake it again for this scene",
          where, scene.name, set.scene_hash, hash));
  } catch (...) {
    scene.meshes = std::move(meshes);
    scene.instances = std::move(instances);
    throw;
  }
}

}  // namespace illum::baked
