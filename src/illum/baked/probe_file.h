// The folder `illum bake --kind probes` writes: an irradiance-probe grid (bake/probe_baker.h)
// and its records.
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
// Written whole or not at all (write_bake_folder, lightmap_file.h); an existing folder is replaced
// only when it holds an earlier probe set (a probes.json).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum::baked {

inline constexpr int kProbeBands = 3;  // SH-L2
inline constexpr int kProbeCoefficients = 9;
// A grid whose probe records would take more than this many bytes is refused
// (bake/probe_baker.h: make_probe_grid), before anything is allocated: 1 GiB is 5.7 million
// probes, 30–70 minutes of baking on 2 cores at the default spp (0.3–0.7 s per 1000 probes at
// 256 spp, docs/probes.md) and far more than the per-object lookups of the renderer need; a
// finer spacing is almost always a typo.
inline constexpr double kMaxProbeBytes = double(1u << 30);
inline constexpr float kDefaultBackfaceThreshold = 0.25f;

// One probe as stored (trivially copyable: the bake's records cross MPI ranks as bytes and
// the data file holds them as they are).
struct ProbeRecord {
  float irradiance[kProbeCoefficients * 3];  // E_i RGB, [i][rgb], world frame (pole +z)
  float cube[6 * 3];                         // E/π at +x, −x, +y, −y, +z, −z, [face][rgb]
  float backface_fraction;                   // share of directions that hit a back face first
  float weight;                              // 1 valid, 0 invalid
};
static_assert(sizeof(ProbeRecord) == 47 * sizeof(float));

// probes at origin + spacing·(x, y, z), index (z·ny + y)·nx + x (realtime::ProbeVolume's).
struct ProbeGrid {
  glm::ivec3 size{0};
  vec3 origin{0.0f};
  float spacing = 0.0f;
  int64_t count() const { return int64_t(size.x) * size.y * size.z; }
  vec3 position(int x, int y, int z) const { return origin + spacing * vec3(x, y, z); }
  vec3 position(int64_t index) const;
};

// A scene copy without the instances marked dynamic: what probes (and their scene_hash)
// are baked from. Meshes only dynamic instances use stay (unreferenced; the hash covers them,
// harmlessly, as the same file always loads them).
Scene static_part(const Scene& scene);

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

}  // namespace illum::baked
