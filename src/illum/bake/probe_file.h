// The folder `illum bake --kind probes` writes: an irradiance-probe grid (probe_baker.h).
// Format, version 1 (docs/probes.md):
//   probes.json  manifest: format "illum-probes", version 1, scene (name), scene_triangles
//                and scene_hash (geometry_hash of the scene's static part, bake/probe_baker.h
//                static_part: instances marked dynamic left out, so moving them keeps the
//                bake), grid {size [nx, ny, nz], origin [x, y, z], spacing} (probe (x, y, z)
//                at origin + spacing·(x, y, z), record index (z·ny + y)·nx + x),
//                sh_bands 3, backface_threshold, probes (count), valid (count), data (file
//                name), and the bake's own numbers under "bake"
//   probes.bin   "ILLUMPRB", u32 version 1, u32 floats per probe (47), u64 probes, then
//                per probe 47 little-endian f32: 27 irradiance SH-L2 coefficients E_i
//                ([i][rgb], i = l(l+1)+m, world frame, pole +z, core/sh.h), 18 ambient-cube
//                values E/π ([face][rgb], faces +x, −x, +y, −y, +z, −z), the back-face
//                share, the weight (1 valid, 0 invalid); nothing may follow
// Written whole or not at all (atlas::write_bake_folder); an existing folder is replaced
// only when it holds an earlier probe set (a probes.json).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/bake/probe_baker.h"
#include "illum/scene/scene.h"

namespace illum::bake {

struct ProbeSet {
  ProbeGrid grid;
  std::vector<ProbeRecord> probes;  // grid.count() records
  float backface_threshold = kDefaultBackfaceThreshold;
  std::string scene;
  size_t scene_triangles = 0;  // of static_part(scene)
  std::string scene_hash;      // geometry_hash_hex(static_part(scene))
  std::string folder;          // where load_probe_set read it from (messages)
  nlohmann::json bake = nlohmann::json::object();
};

// Throws Error unless `folder` can be written (parent exists; absent or an earlier probe set).
void check_probe_output(const std::filesystem::path& folder);
void save_probe_set(const std::filesystem::path& folder, const ProbeSet& set);
// Throws Error naming the file and the problem (missing, malformed JSON, wrong format or
// version, a bad grid, sizes, truncated or trailing data, non-finite values, a weight other
// than 0 or 1).
ProbeSet load_probe_set(const std::filesystem::path& folder);
// Throws Error (one line naming the folder and both scenes) unless `scene` is the one the set
// was baked for: the same triangle count and geometry hash of its static part.
void check_probe_scene(const Scene& scene, const ProbeSet& set);
// load_probe_set, then check_probe_scene: the reader that takes a scene.
ProbeSet load_probe_set_for(const std::filesystem::path& folder, const Scene& scene);

}  // namespace illum::bake
