#include "illum/baked/prt_file.h"

#include <cmath>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "illum/baked/lightmap_file.h"
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

void write_block(const fs::path& path, uint32_t channels, const float* data, uint64_t points) {
  write_file_atomically(path.string(),
                        {bytes_of(kMagic, 8), bytes_of(&kVersion), bytes_of(&channels),
                         bytes_of(&points), bytes_of(data, points * channels)});
}

// Reads a block of exactly `points` × `channels` finite floats.
std::vector<float> read_block(const fs::path& path, uint32_t channels, uint64_t points) {
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
    throw Error(fmt::format("{}: holds {} points × {} channels, the manifest needs {} × {}", where,
                            file_points, file_channels, points, channels));
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

// A manifest field of the right type, or an Error naming the manifest and the key.
const nlohmann::json& field(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.contains(key)) throw Error(fmt::format("{}: '{}' is missing", where, key));
  return j.at(key);
}
uint64_t unsigned_field(const nlohmann::json& j, const char* key, const std::string& where,
                        uint64_t max) {
  const nlohmann::json& v = field(j, key, where);
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<int64_t>() >= 0))
    throw Error(fmt::format("{}: '{}' must be a non-negative integer", where, key));
  if (v.get<uint64_t>() > max)
    throw Error(fmt::format("{}: '{}' = {} is larger than {}", where, key, v.get<uint64_t>(), max));
  return v.get<uint64_t>();
}
std::string string_field(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = field(j, key, where);
  if (!v.is_string()) throw Error(fmt::format("{}: '{}' must be a string", where, key));
  return v.get<std::string>();
}
// A plain file name inside the folder.
std::string file_field(const nlohmann::json& j, const char* key, const std::string& where) {
  const std::string name = string_field(j, key, where);
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
      name.find('\\') != std::string::npos)
    throw Error(
        fmt::format("{}: '{}' must be a file name inside the folder, not '{}'", where, key, name));
  return name;
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
      std::ofstream out(staging / kVqIndexFile, std::ios::binary);
      const uint32_t header[3] = {kVersion, uint32_t(set.atlas.width), uint32_t(set.atlas.height)};
      out.write(kIndexMagic, 8);
      out.write(reinterpret_cast<const char*>(header), sizeof(header));
      out.write(reinterpret_cast<const char*>(set.vq.indices.data()),
                std::streamsize(set.vq.indices.size() * sizeof(uint16_t)));
      if (!out) throw Error(fmt::format("{}: cannot write", (staging / kVqIndexFile).string()));
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
  if (!j.is_object()) throw Error(fmt::format("{}: must be a JSON object", mw));
  if (!field(j, "format", mw).is_string() || j.at("format") != "illum-prt" ||
      unsigned_field(j, "version", mw, 1u << 30) != kVersion)
    throw Error(fmt::format("{}: not an illum-prt version {} manifest", mw, kVersion));
  PrtSet set;
  set.folder = where;
  set.bands = int(unsigned_field(j, "bands", mw, 1u << 30));
  if (set.bands < kMinPrtBands || set.bands > kMaxPrtBands)
    throw Error(fmt::format("{}: bands = {} must lie in [{}, {}]", mw, set.bands, kMinPrtBands,
                            kMaxPrtBands));
  try {
    set.mode = prt_mode_from_string(string_field(j, "mode", mw));
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", mw, e.what()));
  }
  set.scene = string_field(j, "scene", mw);
  set.scene_triangles = unsigned_field(j, "scene_triangles", mw, uint64_t{1} << 40);
  set.scene_hash = string_field(j, "scene_hash", mw);
  if (set.scene_hash.size() != 16 ||
      set.scene_hash.find_first_not_of("0123456789abcdef") != std::string::npos)
    throw Error(fmt::format("{}: 'scene_hash' must be 16 lowercase hex digits", mw));
  if (j.contains("bake")) set.bake = j.at("bake");
  set.atlas = atlas::load_atlas(folder / file_field(j, "atlas", mw));
  if (unsigned_field(j, "width", mw, 1u << 30) != uint64_t(set.atlas.width) ||
      unsigned_field(j, "height", mw, 1u << 30) != uint64_t(set.atlas.height))
    throw Error(fmt::format("{}: width/height differ from the atlas's {}x{}", mw, set.atlas.width,
                            set.atlas.height));
  const uint32_t channels = uint32_t(3 * sh::coefficient_count(set.bands));
  if (j.contains("texels")) {
    const uint64_t points = uint64_t(set.atlas.width) * uint64_t(set.atlas.height);
    std::vector<float> data = read_block(folder / file_field(j, "texels", mw), channels, points);
    set.texel_transfer = TransferMap(set.atlas.width, set.atlas.height, int(channels));
    set.texel_transfer.data = std::move(data);
  }
  if (j.contains("vertices")) {
    const nlohmann::json& v = j.at("vertices");
    if (!v.is_object()) throw Error(fmt::format("{}: 'vertices' must be an object", mw));
    const nlohmann::json& counts = field(v, "vertex_counts", mw);
    if (!counts.is_array()) throw Error(fmt::format("{}: 'vertex_counts' must be a list", mw));
    uint64_t total = 0;
    std::vector<uint64_t> each;
    for (const nlohmann::json& c : counts) {
      if (!c.is_number_unsigned() || c.get<uint64_t>() > (uint64_t{1} << 32))
        throw Error(fmt::format("{}: 'vertex_counts' must hold integers in [0, 2^32]", mw));
      each.push_back(c.get<uint64_t>());
      total += each.back();
    }
    const std::vector<float> data = read_block(folder / file_field(v, "file", mw), channels, total);
    size_t at = 0;
    for (uint64_t c : each) {
      set.vertex_transfer.emplace_back(data.begin() + std::ptrdiff_t(at),
                                       data.begin() + std::ptrdiff_t(at + c * channels));
      at += c * channels;
    }
  }
  if (j.contains("vq")) {
    const nlohmann::json& v = j.at("vq");
    if (!v.is_object()) throw Error(fmt::format("{}: 'vq' must be an object", mw));
    const uint64_t count = unsigned_field(v, "representatives", mw, kMaxVqRepresentatives);
    if (count == 0) throw Error(fmt::format("{}: 'vq' needs at least one representative", mw));
    set.vq.dimension = int(channels);
    set.vq.representatives = read_block(folder / file_field(v, "file", mw), channels, count);
    const fs::path ipath = folder / file_field(v, "indices", mw);
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
