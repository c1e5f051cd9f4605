#include "illum/scene/load.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/ranges.h>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/loaders.h"
#include "illum/scene/mesh_processing.h"

#ifndef ILLUM_DATA_DIR
#define ILLUM_DATA_DIR "data"
#endif
#ifndef ILLUM_SHARED_SCENES
#define ILLUM_SHARED_SCENES "../shared/scenes"
#endif
#ifndef ILLUM_INSTALLED_DATA_DIR
#define ILLUM_INSTALLED_DATA_DIR "../share/illum"
#endif

namespace illum {

namespace detail {

std::string parent_dir(const std::string& path) {
  return std::filesystem::path(path).parent_path().string();
}

std::string join_path(const std::string& dir, const std::string& relative) {
  const std::filesystem::path rel(relative);
  if (rel.is_absolute() || dir.empty()) return rel.lexically_normal().string();
  return (std::filesystem::path(dir) / rel).lexically_normal().string();
}

bool file_exists(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void missing_texture(Scene& scene, const LoadOptions& options, const std::string& message) {
  if (!options.allow_missing_textures) throw Error(message);
  add_warning(scene, message + "; going on without it (--allow-missing-textures)");
}

int TextureCache::get(const std::string& path, bool srgb, const std::string& user) {
  if (!options_.load_textures) return kNoTexture;
  const auto key = std::make_pair(path, srgb);
  if (auto it = ids_.find(key); it != ids_.end()) return it->second;
  int id = kNoTexture;
  if (!file_exists(path)) {
    missing_texture(
        scene_, options_,
        fmt::format("{}: texture '{}' of material '{}' not found", origin_, path, user));
  } else {
    try {
      Texture tex;
      tex.path = path;
      tex.srgb = srgb;
      tex.image = read_image(path, srgb);
      id = static_cast<int>(scene_.textures.size());
      scene_.textures.push_back(std::move(tex));
    } catch (const Error& e) {
      // e names the texture file and what is wrong with it.
      missing_texture(scene_, options_,
                      fmt::format("{}: texture of material '{}': {}", origin_, user, e.what()));
    }
  }
  ids_[key] = id;
  return id;
}

}  // namespace detail

std::string data_dir() {
  const char* env = std::getenv("ILLUM_DATA_DIR");
  if (env != nullptr && env[0] != '\0') return env;
  // Found from the running program, not a path compiled in: an installed tree may be moved
  // (or installed with DESTDIR), and the build tree it came from may be gone.
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed =
        (exe.parent_path() / ILLUM_INSTALLED_DATA_DIR).lexically_normal();
    if (std::filesystem::is_directory(installed / "scenes", ec)) return installed.string();
  }
  return ILLUM_DATA_DIR;
}

std::string shared_scenes_dir() {
  const char* env = std::getenv("ILLUM_SHARED_SCENES");
  if (env != nullptr && env[0] != '\0') return env;
  return ILLUM_SHARED_SCENES;
}

std::vector<std::string> builtin_scene_names() {
  return {"caustics", "cornell", "cornell-spot", "envroom", "sibenik"};
}

Scene load_scene(const std::string& path_or_name, const LoadOptions& options) {
  std::string path = path_or_name;
  std::string name;
  const auto builtins = builtin_scene_names();
  if (std::find(builtins.begin(), builtins.end(), path_or_name) != builtins.end() &&
      !detail::file_exists(path_or_name)) {
    name = path_or_name;
    path = detail::join_path(data_dir(),
                             "scenes/" + path_or_name + "/" + path_or_name + ".illum.json");
  }
  const std::string ext = detail::lower_extension(path);
  if (ext != ".obj" && ext != ".gltf" && ext != ".glb" && ext != ".json") {
    if (ext.empty() && !detail::file_exists(path))
      throw Error(fmt::format("'{}' is neither a scene file nor a built-in scene ({})", path,
                              fmt::join(builtins, ", ")));
    throw Error(
        fmt::format("{}: unknown scene format '{}' (expected .obj, .gltf, .glb or "
                    ".illum.json)",
                    path, ext));
  }
  if (!detail::file_exists(path)) throw Error(fmt::format("{}: cannot open file", path));

  Scene scene;
  try {
    if (ext == ".obj") {
      scene = detail::load_obj(path, options);
    } else if (ext == ".gltf" || ext == ".glb") {
      scene = detail::load_gltf(path, options);
    } else {
      scene = detail::load_illum_json(path, options);
    }
    finalize_scene(scene, path);
  } catch (const Error&) {
    throw;
  } catch (const InternalError&) {
    throw;
  } catch (const std::bad_alloc&) {
    // The loaders check declared sizes against the bytes that exist; this is the last line.
    throw Error(fmt::format("{}: out of memory while loading the scene", path));
  } catch (const std::exception& e) {
    // A parser library's own exception (nlohmann, tinygltf, the standard library) is still
    // bad input: one line naming the file, exit code 2, never the CLI's generic failure.
    throw Error(fmt::format("{}: {}", path, e.what()));
  }
  if (name.empty()) {
    name = std::filesystem::path(path).filename().string();
    for (const char* suffix : {".illum.json", ".json", ".gltf", ".glb", ".obj"}) {
      const std::string s(suffix);
      if (name.size() > s.size() && detail::lower_extension(name) != "" &&
          std::equal(s.rbegin(), s.rend(), name.rbegin(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) ==
                   std::tolower(static_cast<unsigned char>(b));
          })) {
        name.resize(name.size() - s.size());
        break;
      }
    }
  }
  if (scene.name.empty()) scene.name = name;
  scene.source_path = path;
  // Warnings reach the log only now, after the whole load succeeded: a failing load prints its
  // one error line and nothing before it.
  for (const std::string& warning : scene.warnings) log::warn("{}", warning);
  log::debug("{}: {} meshes, {} instances, {} triangles, {} materials, {} lights", path,
             scene.meshes.size(), scene.instances.size(), scene.triangle_count(),
             scene.materials.size(), scene.lights.size());
  return scene;
}

}  // namespace illum
