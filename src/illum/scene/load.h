// Scene loading: glTF 2.0 (.gltf/.glb), OBJ/MTL (.obj), illum scene files (.illum.json),
// and built-in scenes by name ("cornell", "caustics", "sibenik").
#pragma once

#include <string>
#include <vector>

#include "illum/scene/scene.h"

namespace illum {

struct LoadOptions {
  bool load_textures = true;
  // A texture file that is missing or cannot be decoded is an error naming it (the README
  // promises that missing files are errors); with this set it is one warning instead and
  // the material renders without it (`--allow-missing-textures` on the command line).
  bool allow_missing_textures = false;
};

// Loads `path_or_name`: a built-in name or a file path. Validates the result (finite
// vertices, in-range indices and material ids), drops degenerate triangles with one
// warning that counts them, fills missing normals and tangents. Throws illum::Error
// with a one-line message naming the file on anything malformed.
Scene load_scene(const std::string& path_or_name, const LoadOptions& options = {});

// Names accepted by load_scene without a path.
std::vector<std::string> builtin_scene_names();

// The project's data folder: $ILLUM_DATA_DIR if set; else share/illum beside an installed
// program (<prefix>/bin/illum finds <prefix>/share/illum, so an installed copy never reads
// the build tree); else the checkout's data/ compiled in.
std::string data_dir();

// The folder of the shared scenes that a scene file names as `${shared_scenes}/...` (the
// built-in sibenik's OBJ, too large for the repository): $ILLUM_SHARED_SCENES if set, else
// ../shared/scenes beside the checkout, compiled in.
std::string shared_scenes_dir();

}  // namespace illum
