// Internal to the scene layer: the per-format loaders load_scene dispatches to. Each returns
// a scene whose meshes are validated (errors name the file) but not yet finalized
// (finalize_scene drops degenerates, fills normals/tangents, adds area lights).
#pragma once

#include <map>
#include <string>
#include <utility>

#include "illum/scene/load.h"
#include "illum/scene/scene.h"

namespace illum::detail {

Scene load_obj(const std::string& path, const LoadOptions& options);
Scene load_gltf(const std::string& path, const LoadOptions& options);
Scene load_illum_json(const std::string& path, const LoadOptions& options);

// A texture, material file or environment map that is missing or cannot be read: throws
// Error(message) (the message names the file and, for textures, the material), or with
// LoadOptions::allow_missing_textures adds it as one warning and the scene goes on without.
void missing_texture(Scene& scene, const LoadOptions& options, const std::string& message);

// Loads image files into Scene::textures once per (path, encoding). A missing or unreadable
// file goes through missing_texture (an error, or one warning and kNoTexture).
class TextureCache {
 public:
  TextureCache(Scene& scene, const LoadOptions& options, std::string origin)
      : scene_(scene), options_(options), origin_(std::move(origin)) {}
  // `user` names the material for the warning.
  int get(const std::string& path, bool srgb, const std::string& user);

 private:
  Scene& scene_;
  const LoadOptions& options_;
  std::string origin_;
  std::map<std::pair<std::string, bool>, int> ids_;
};

// Directory part of a path ("" for a bare name) and path joining that keeps absolute paths.
std::string parent_dir(const std::string& path);
std::string join_path(const std::string& dir, const std::string& relative);
bool file_exists(const std::string& path);
// Lower-case extension including the dot (".obj"); ".illum.json" counts as ".json".
std::string lower_extension(const std::string& path);

}  // namespace illum::detail
