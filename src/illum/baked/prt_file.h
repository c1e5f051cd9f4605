// The folder `illum bake --kind prt` writes and `illum relight` reads: baked PRT transfer
// (bake/prt_baker.h) and its data types. Format, version 1 (docs/prt.md):
//   prt.json      manifest: format "illum-prt", version 1, bands, mode, coefficients
//                 (bands²), scene name, scene_triangles, scene_hash (geometry_hash of the
//                 scene with the atlas applied, as the light-map folder records it), atlas
//                 file, width, height, texel_size, charts, "texels" (file, or absent),
//                 "vertices" (file and vertex_counts per instance, or absent), and the
//                 bake's own numbers under "bake"
//   atlas.bin     the atlas (atlas/atlas.h), to put uv1 on the scene again
//   texels.bin    transfer per texel, dense over the atlas (dilated)
//   vertices.bin  transfer per vertex, instances in Scene order
//   vq_representatives.bin, vq_indices.bin   with --vq: the representatives (the block
//                 format below, points = representatives) and "ILLUMPRI" u32 version 1,
//                 u32 width, u32 height, width·height little-endian u16 indices; listed
//                 under "vq" in the manifest
//   preview.png   coefficient 0 of the texel map (the transfer under a constant sky), for people
// Both .bin files: "ILLUMPRT" u32 version = 1, u32 channels (3·bands²), u64 points, then
// points × channels little-endian f32 ([point][i][rgb]); nothing may follow.
// Written next to its final place and renamed into it, as the light-map folder: a failed or
// interrupted bake leaves nothing half-written, and an existing folder is replaced only when
// it holds an earlier PRT set (a prt.json).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/atlas/atlas.h"
#include "illum/core/image.h"
#include "illum/scene/scene.h"

namespace illum::baked {

enum class PrtMode { kUnshadowed, kShadowed, kInterreflected };
const char* to_string(PrtMode mode);
PrtMode prt_mode_from_string(const std::string& name);  // unshadowed|shadowed|interreflected

inline constexpr int kMinPrtBands = 2;
inline constexpr int kMaxPrtBands = 8;

// A raster of transfer vectors (core Image holds at most 4 channels; this holds 3·bands²).
struct TransferMap {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;  // row-major, `channels` floats per texel
  TransferMap() = default;
  TransferMap(int w, int h, int c)
      : width(w), height(h), channels(c), data(size_t(w) * size_t(h) * size_t(c), 0.0f) {}
  bool empty() const { return data.empty(); }
  float* pixel(int x, int y) {
    return &data[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels)];
  }
  const float* pixel(int x, int y) const {
    return &data[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels)];
  }
};

inline constexpr int kMaxVqRepresentatives = 1 << 16;

// A VQ-compressed transfer map (bake/prt_vq.h: vq_compress).
struct VqCodebook {
  int dimension = 0;
  std::vector<float> representatives;  // count × dimension
  std::vector<uint16_t> indices;       // one per vector: its nearest representative
  int iterations = 0;
  double max_distance = 0.0;  // max over vectors of |v − r(v)| (Euclidean)
  double rms_distance = 0.0;
  int count() const { return dimension ? int(representatives.size() / size_t(dimension)) : 0; }
};

struct PrtSet {
  atlas::Atlas atlas;
  int bands = 0;
  PrtMode mode = PrtMode::kShadowed;
  TransferMap texel_transfer;                       // empty: no texels baked
  std::vector<std::vector<float>> vertex_transfer;  // empty: no vertices baked
  // VQ-compressed texel transfer (bake/prt_vq.h): one index per texel of the atlas, row-major;
  // count() == 0 when the bake was not compressed.
  VqCodebook vq;
  std::string scene;
  size_t scene_triangles = 0;
  std::string scene_hash;
  std::string folder;  // where load_prt_set read it from (messages)
  nlohmann::json bake = nlohmann::json::object();
};

// Throws Error unless `folder` can be written (parent exists; absent or an earlier PRT set).
void check_prt_output(const std::filesystem::path& folder);
void save_prt_set(const std::filesystem::path& folder, const PrtSet& set);
// Throws Error naming the file and the problem (missing, malformed JSON, wrong format,
// version, bands, mode, sizes, truncated or trailing data, non-finite values).
PrtSet load_prt_set(const std::filesystem::path& folder);
// Puts the set's atlas on `scene` after checking the scene is the one it was baked for (the
// light-map folder's check: triangle count, then geometry hash) and that the vertex counts
// match; throws Error (one line naming the folder) and leaves `scene` unchanged otherwise.
void apply_prt_set(Scene& scene, const PrtSet& set);

}  // namespace illum::baked
