#include "illum/baked/prt_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "illum/baked/lightmap_file.h"
#include "illum/baked/manifest_fields.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"
#include "illum/core/json_input.h"
#include "illum/core/sh.h"
#include "illum/core/tonemap.h"

namespace illum::baked {

namespace fs = std::filesystem;

namespace {

constexpr const char* kManifest = "prt.json";
constexpr const char* kAtlasFile = "atlas.bin";
constexpr const char* kTexelFile = "texels.bin";
constexpr const char* kVertexFile = "vertices.bin";
constexpr const char* kVqFile = "vq_representatives.bin";
constexpr const char* kVqIndexFile = "vq_indices.bin";
constexpr char kMagic[8] = {'I', 'L', 'L', 'U', 'M', 'P', 'R', 'T'};
constexpr char kIndexMagic[8] = {'I', 'L', 'L', 'U', 'M', 'P', 'R', 'I'};
constexpr uint32_t kVersion = 1;
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8;
// Vertices of all instances of a vertex-transfer block (Embree numbers them in 32 bits).
constexpr uint64_t kMaxPrtVertices = uint64_t{1} << 32;

void write_block(const fs::path& path, uint32_t channels, const float* data, uint64_t points) {
  write_file_atomically(path.string(),
                        {bytes_of(kMagic, 8), bytes_of(&kVersion), bytes_of(&channels),
                         bytes_of(&points), bytes_of(data, points * channels)});
}

// Reads a block of exactly `points` × `channels` finite floats. `field` names the entry of
// `manifest` that sets `points`: a file that disagrees with it is refused naming both.
std::vector<float> read_block(const fs::path& path, uint32_t channels, uint64_t points,
                              const ManifestFields& manifest, const char* field) {
  const std::string where = path.string();
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(fmt::format("{}: cannot open", where));
  const uint64_t bytes = uint64_t(in.tellg());
  in.seekg(0);
  char magic[8];
  uint32_t version = 0, file_channels = 0;
  uint64_t file_points = 0;
  if (bytes < kHeaderBytes) throw Error(fmt::format("{}: truncated header", where));
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&version), 4);
  in.read(reinterpret_cast<char*>(&file_channels), 4);
  in.read(reinterpret_cast<char*>(&file_points), 8);
  if (std::memcmp(magic, kMagic, 8) != 0 || version != kVersion)
    throw Error(fmt::format("{}: not an ILLUMPRT version {} file", where, kVersion));
  if (file_channels != channels || file_points != points)
    manifest.fail(fmt::format("'{}' needs {} points × {} channels, but {} holds {} × {}", field,
                              points, channels, path.filename().string(), file_points,
                              file_channels));
  const uint64_t expected = kHeaderBytes + points * channels * sizeof(float);
  if (bytes != expected)
    throw Error(fmt::format("{}: {} bytes, {} expected ({})", where, bytes, expected,
                            bytes < expected ? "truncated" : "trailing data"));
  std::vector<float> data(points * channels);
  in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
  if (!in) throw Error(fmt::format("{}: read error", where));
  for (size_t i = 0; i < data.size(); ++i)
    if (!std::isfinite(data[i]))
      throw Error(
          fmt::format("{}: value {} of point {} is not finite", where, i % channels, i / channels));
  return data;
}

}  // namespace

const char* to_string(PrtMode mode) {
  switch (mode) {
    case PrtMode::kUnshadowed:
      return "unshadowed";
    case PrtMode::kShadowed:
      return "shadowed";
    case PrtMode::kInterreflected:
      return "interreflected";
  }
  return "?";
}

PrtMode prt_mode_from_string(const std::string& name) {
  if (name == "unshadowed") return PrtMode::kUnshadowed;
  if (name == "shadowed") return PrtMode::kShadowed;
  if (name == "interreflected") return PrtMode::kInterreflected;
  throw Error(fmt::format("unknown PRT mode '{}' (unshadowed, shadowed or interreflected)", name));
}

void check_prt_output(const fs::path& folder) {
  check_bake_output(folder, kManifest, "PRT");
}

void save_prt_set(const fs::path& folder, const PrtSet& set) {
  if (set.bands < kMinPrtBands || set.bands > kMaxPrtBands)
    throw Error(fmt::format("PRT set: bands = {} out of range", set.bands));
  const uint32_t channels = uint32_t(3 * sh::coefficient_count(set.bands));
  if (!set.texel_transfer.empty() && (set.texel_transfer.width != set.atlas.width ||
                                      set.texel_transfer.height != set.atlas.height ||
                                      set.texel_transfer.channels != int(channels)))
    throw Error("PRT set: the texel transfer does not match the atlas and bands");
  for (const auto& v : set.vertex_transfer)
    if (v.size() % channels != 0) throw Error("PRT set: a vertex transfer is not whole points");
  check_prt_output(folder);
  write_bake_folder(folder, kManifest, [&](const fs::path& staging) {
    nlohmann::json manifest = {{"format", "illum-prt"},
                               {"version", kVersion},
                               {"bands", set.bands},
                               {"coefficients", sh::coefficient_count(set.bands)},
                               {"mode", to_string(set.mode)},
                               {"scene", set.scene},
                               {"scene_triangles", set.scene_triangles},
                               {"scene_hash", set.scene_hash},
                               {"atlas", kAtlasFile},
                               {"width", set.atlas.width},
                               {"height", set.atlas.height},
                               {"texel_size", set.atlas.texel_size},
                               {"charts", set.atlas.chart_count},
                               {"bake", set.bake}};
    save_atlas(set.atlas, staging / kAtlasFile);
    if (!set.texel_transfer.empty()) {
      write_block(staging / kTexelFile, channels, set.texel_transfer.data.data(),
                  uint64_t(set.atlas.width) * uint64_t(set.atlas.height));
      manifest["texels"] = kTexelFile;
      // Coefficient 0 × 2√π: E/π under a constant unit sky, in [0, 1] without bounces.
      Image preview(set.atlas.width, set.atlas.height, 3);
      const float sky = float(1.0 / sh::kY00);
      for (int y = 0; y < preview.height(); ++y)
        for (int x = 0; x < preview.width(); ++x) {
          const float* t = set.texel_transfer.pixel(x, y);
          preview.set_rgb(x, y, Color(t[0], t[1], t[2]) * sky);
        }
      write_image((staging / "preview.png").string(),
                  tone_mapped(preview, ToneMapper::kClamp, 1.0f));
    }
    if (set.vq.count() > 0) {
      if (set.vq.dimension != int(channels) ||
          set.vq.indices.size() != size_t(set.atlas.width) * size_t(set.atlas.height))
        throw Error("PRT set: the VQ codebook does not match the atlas and bands");
      write_block(staging / kVqFile, channels, set.vq.representatives.data(),
                  uint64_t(set.vq.count()));
      const uint32_t header[3] = {kVersion, uint32_t(set.atlas.width), uint32_t(set.atlas.height)};
      write_file_atomically((staging / kVqIndexFile).string(),
                            {bytes_of(kIndexMagic, 8), bytes_of(header, 3),
                             bytes_of(set.vq.indices.data(), set.vq.indices.size())});
      manifest["vq"] = {{"representatives", set.vq.count()},
                        {"file", kVqFile},
                        {"indices", kVqIndexFile},
                        {"iterations", set.vq.iterations},
                        {"max_distance", set.vq.max_distance},
                        {"rms_distance", set.vq.rms_distance}};
    }
    if (!set.vertex_transfer.empty()) {
      std::vector<float> all;
      nlohmann::json counts = nlohmann::json::array();
      for (const auto& v : set.vertex_transfer) {
        all.insert(all.end(), v.begin(), v.end());
        counts.push_back(v.size() / channels);
      }
      write_block(staging / kVertexFile, channels, all.data(), all.size() / channels);
      manifest["vertices"] = {{"file", kVertexFile}, {"vertex_counts", counts}};
    }
    return manifest;
  });
}

PrtSet load_prt_set(const fs::path& folder) {
  const std::string where = folder.string();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(fmt::format("PRT folder '{}' does not exist", where));
  const std::string mw = fmt::format("{}/{}", where, kManifest);
  if (!fs::is_regular_file(folder / kManifest, ec))
    throw Error(fmt::format("{}: no {} (not a PRT folder)", where, kManifest));
  const nlohmann::json j = read_json_file(mw);
  const ManifestFields manifest(j, mw);
  manifest.expect_format("illum-prt", kVersion);
  PrtSet set;
  set.folder = where;
  set.bands = int(manifest.integer("bands", kMinPrtBands, kMaxPrtBands));
  // Redundant with bands, so a disagreement is a damaged or hand-edited manifest.
  const uint64_t coefficients = uint64_t(sh::coefficient_count(set.bands));
  manifest.integer("coefficients", coefficients, coefficients);
  set.mode =
      prt_mode_from_string(manifest.one_of("mode", {"unshadowed", "shadowed", "interreflected"}));
  set.scene = manifest.string("scene");
  set.scene_triangles = manifest.integer("scene_triangles", 0, kMaxManifestTriangles);
  set.scene_hash = manifest.scene_hash("scene_hash");
  if (manifest.has("bake")) set.bake = manifest.free_object("bake");
  set.atlas = read_manifest_atlas(manifest, folder);
  const uint32_t channels = uint32_t(3 * coefficients);
  if (manifest.has("texels")) {
    const uint64_t points = uint64_t(set.atlas.width) * uint64_t(set.atlas.height);
    std::vector<float> data =
        read_block(folder / manifest.file_name("texels"), channels, points, manifest, "texels");
    set.texel_transfer = TransferMap(set.atlas.width, set.atlas.height, int(channels));
    set.texel_transfer.data = std::move(data);
  }
  if (manifest.has("vertices")) {
    const ManifestFields v = manifest.object("vertices");
    const nlohmann::json& counts = v.at("vertex_counts");
    if (!counts.is_array())
      v.fail(fmt::format("'vertices.vertex_counts' must be a list, not {}",
                         ManifestFields::shown(counts)));
    // Bounded one by one and in total, so the sum cannot wrap; read_block then checks the
    // total against the file's size before allocating.
    uint64_t total = 0;
    std::vector<uint64_t> each;
    for (const nlohmann::json& c : counts) {
      if (!(c.is_number_unsigned() || (c.is_number_integer() && c.get<int64_t>() >= 0)) ||
          c.get<uint64_t>() > kMaxPrtVertices || total + c.get<uint64_t>() > kMaxPrtVertices)
        v.fail(
            fmt::format("'vertices.vertex_counts' must hold integers ≥ 0 summing to at most {}, "
                        "not {}",
                        kMaxPrtVertices, ManifestFields::shown(c)));
      each.push_back(c.get<uint64_t>());
      total += each.back();
    }
    const std::vector<float> data =
        read_block(folder / v.file_name("file"), channels, total, v, "vertices.vertex_counts");
    size_t at = 0;
    for (uint64_t c : each) {
      set.vertex_transfer.emplace_back(data.begin() + std::ptrdiff_t(at),
                                       data.begin() + std::ptrdiff_t(at + c * channels));
      at += c * channels;
    }
  }
  if (manifest.has("vq")) {
    const ManifestFields v = manifest.object("vq");
    const uint64_t count = v.integer("representatives", 1, kMaxVqRepresentatives);
    // The quantizer's own record: checked for type and range though nothing reads them back.
    v.integer("iterations", 0, uint64_t{1} << 31);
    v.number("max_distance", 0.0, std::numeric_limits<float>::max());
    v.number("rms_distance", 0.0, std::numeric_limits<float>::max());
    set.vq.dimension = int(channels);
    set.vq.representatives =
        read_block(folder / v.file_name("file"), channels, count, v, "vq.representatives");
    const fs::path ipath = folder / v.file_name("indices");
    const std::string iw = ipath.string();
    std::ifstream in(ipath, std::ios::binary | std::ios::ate);
    if (!in) throw Error(fmt::format("{}: cannot open", iw));
    const uint64_t bytes = uint64_t(in.tellg());
    in.seekg(0);
    const uint64_t texels = uint64_t(set.atlas.width) * uint64_t(set.atlas.height);
    const uint64_t expected = 8 + 12 + texels * 2;
    char magic[8];
    uint32_t header[3] = {0, 0, 0};
    if (bytes >= 20) {
      in.read(magic, 8);
      in.read(reinterpret_cast<char*>(header), sizeof(header));
    }
    if (bytes < 20 || std::memcmp(magic, kIndexMagic, 8) != 0 || header[0] != kVersion)
      throw Error(fmt::format("{}: not an ILLUMPRI version {} file", iw, kVersion));
    if (header[1] != uint32_t(set.atlas.width) || header[2] != uint32_t(set.atlas.height))
      throw Error(fmt::format("{}: {}x{} indices for a {}x{} atlas", iw, header[1], header[2],
                              set.atlas.width, set.atlas.height));
    if (bytes != expected)
      throw Error(fmt::format("{}: {} bytes, {} expected", iw, bytes, expected));
    set.vq.indices.resize(texels);
    in.read(reinterpret_cast<char*>(set.vq.indices.data()), std::streamsize(texels * 2));
    for (size_t i = 0; i < set.vq.indices.size(); ++i)
      if (set.vq.indices[i] >= count)
        throw Error(fmt::format("{}: index {} of texel {} is not below {} representatives", iw,
                                set.vq.indices[i], i, count));
  }
  if (set.texel_transfer.empty() && set.vertex_transfer.empty())
    throw Error(fmt::format("{}: holds neither 'texels' nor 'vertices'", mw));
  return set;
}

void apply_prt_set(Scene& scene, const PrtSet& set) {
  LightmapSet identity;  // the light-map folder's scene check, reused as it is
  identity.atlas = set.atlas;
  identity.scene = set.scene;
  identity.scene_triangles = set.scene_triangles;
  identity.scene_hash = set.scene_hash;
  identity.folder = set.folder.empty() ? "PRT set" : set.folder;
  std::vector<Mesh> meshes = scene.meshes;
  std::vector<Instance> instances = scene.instances;
  apply_lightmap_set(scene, identity);
  if (!set.vertex_transfer.empty()) {
    const size_t channels = size_t(3 * sh::coefficient_count(set.bands));
    bool fits = set.vertex_transfer.size() == scene.instances.size();
    for (size_t i = 0; fits && i < scene.instances.size(); ++i)
      fits = set.vertex_transfer[i].size() ==
             scene.meshes[size_t(scene.instances[i].mesh)].vertex_count() * channels;
    if (!fits) {
      scene.meshes = std::move(meshes);
      scene.instances = std::move(instances);
      throw Error(fmt::format("{}: vertex counts do not fit scene '{}'; bake it again",
                              identity.folder, scene.name));
    }
  }
}

}  // namespace illum::baked
