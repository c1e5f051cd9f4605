#include "illum/baked/probe_file.h"

#include <cmath>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "illum/baked/lightmap_file.h"
#include "illum/baked/manifest_fields.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"
#include "illum/core/json_input.h"
#include "illum/scene/geometry_hash.h"

namespace illum::baked {

namespace fs = std::filesystem;

namespace {

constexpr const char* kManifest = "probes.json";
constexpr const char* kDataFile = "probes.bin";
constexpr char kMagic[8] = {'I', 'L', 'L', 'U', 'M', 'P', 'R', 'B'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kFloatsPerProbe = uint32_t(sizeof(ProbeRecord) / sizeof(float));
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8;

// Probe positions stay finite in float: a grid a thousand kilometres from the origin, with
// probes up to a thousand kilometres apart, is past any scene.
constexpr double kMaxProbeOrigin = 1e6;
constexpr double kMaxProbeSpacing = 1e6;

}  // namespace

vec3 ProbeGrid::position(int64_t index) const {
  const int64_t x = index % size.x, y = (index / size.x) % size.y,
                z = index / (int64_t(size.x) * size.y);
  return position(int(x), int(y), int(z));
}

Scene static_part(const Scene& scene) {
  Scene out = scene;
  out.instances.clear();
  out.meshes.clear();
  std::vector<int> instance_map(scene.instances.size(), -1);
  std::vector<int> mesh_map(scene.meshes.size(), -1);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    Instance inst = scene.instances[i];
    if (inst.dynamic) continue;
    if (mesh_map[size_t(inst.mesh)] < 0) {
      mesh_map[size_t(inst.mesh)] = int(out.meshes.size());
      out.meshes.push_back(scene.meshes[size_t(inst.mesh)]);
    }
    inst.mesh = mesh_map[size_t(inst.mesh)];
    instance_map[i] = int(out.instances.size());
    out.instances.push_back(inst);
  }
  // Area lights follow their instance; those of dynamic objects go with them.
  out.lights.clear();
  for (Light light : scene.lights) {
    if (light.type == LightType::kArea) {
      if (light.instance < 0 || size_t(light.instance) >= instance_map.size() ||
          instance_map[size_t(light.instance)] < 0)
        continue;
      light.instance = instance_map[size_t(light.instance)];
    }
    out.lights.push_back(light);
  }
  return out;
}

void check_probe_output(const fs::path& folder) {
  check_bake_output(folder, kManifest, "probe");
}

void save_probe_set(const fs::path& folder, const ProbeSet& set) {
  if (set.grid.count() < 1 || size_t(set.grid.count()) != set.probes.size())
    throw Error(fmt::format("probe set: {} records for a {}×{}×{} grid", set.probes.size(),
                            set.grid.size.x, set.grid.size.y, set.grid.size.z));
  check_probe_output(folder);
  int64_t valid = 0;
  for (const ProbeRecord& r : set.probes) valid += r.weight > 0.0f ? 1 : 0;
  write_bake_folder(folder, kManifest, [&](const fs::path& staging) {
    const uint64_t points = set.probes.size();
    write_file_atomically((staging / kDataFile).string(),
                          {bytes_of(kMagic, 8), bytes_of(&kVersion), bytes_of(&kFloatsPerProbe),
                           bytes_of(&points), bytes_of(set.probes.data(), points)});
    const ProbeGrid& g = set.grid;
    return nlohmann::json{
        {"format", "illum-probes"},
        {"version", kVersion},
        {"scene", set.scene},
        {"scene_triangles", set.scene_triangles},
        {"scene_hash", set.scene_hash},
        {"grid",
         {{"size", {g.size.x, g.size.y, g.size.z}},
          {"origin", {g.origin.x, g.origin.y, g.origin.z}},
          {"spacing", g.spacing}}},
        {"sh_bands", kProbeBands},
        {"backface_threshold", set.backface_threshold},
        {"probes", points},
        {"valid", valid},
        {"data", kDataFile},
        {"layout",
         "per probe 47 f32: irradiance SH-L2 [9][rgb] (E, world frame, pole +z), ambient cube "
         "E/pi [6][rgb] (+x,-x,+y,-y,+z,-z), back-face share, weight"},
        {"bake", set.bake}};
  });
}

ProbeSet load_probe_set(const fs::path& folder) {
  const std::string where = folder.string();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(fmt::format("probe folder '{}' does not exist", where));
  if (!fs::is_regular_file(folder / kManifest, ec))
    throw Error(fmt::format("{}: no {} (not a probe folder)", where, kManifest));
  const std::string mw = (folder / kManifest).string();
  const nlohmann::json j = read_json_file(mw);
  const ManifestFields manifest(j, mw);
  manifest.expect_format("illum-probes", kVersion);
  ProbeSet set;
  set.folder = where;
  set.scene = manifest.string("scene");
  set.scene_triangles = manifest.integer("scene_triangles", 0, kMaxManifestTriangles);
  set.scene_hash = manifest.scene_hash("scene_hash");
  manifest.integer("sh_bands", kProbeBands, kProbeBands);
  set.backface_threshold = float(manifest.number("backface_threshold", 0.0, 1.0));
  if (manifest.has("bake")) set.bake = manifest.free_object("bake");
  manifest.string("layout");  // for people; the format is fixed by the version
  const ManifestFields grid = manifest.object("grid");
  const nlohmann::json& size = grid.at("size");
  if (!size.is_array() || size.size() != 3)
    grid.fail(
        fmt::format("'grid.size' must be three integers ≥ 1, not {}", ManifestFields::shown(size)));
  double probes = 1.0;
  for (int a = 0; a < 3; ++a) {
    const nlohmann::json& s = size[size_t(a)];
    if (!s.is_number_integer() || s.get<int64_t>() < 1 || s.get<int64_t>() > (int64_t(1) << 30))
      grid.fail(fmt::format("'grid.size' must be three integers ≥ 1, not {}",
                            ManifestFields::shown(size)));
    set.grid.size[a] = int(s.get<int64_t>());
    probes *= double(set.grid.size[a]);
  }
  if (probes * double(sizeof(ProbeRecord)) > kMaxProbeBytes)
    grid.fail(
        fmt::format("'grid.size' asks for {:.4g} probes, more than the format allows", probes));
  const nlohmann::json& origin = grid.at("origin");
  if (!origin.is_array() || origin.size() != 3)
    grid.fail(
        fmt::format("'grid.origin' must be three numbers, not {}", ManifestFields::shown(origin)));
  for (int a = 0; a < 3; ++a) {
    const nlohmann::json& o = origin[size_t(a)];
    if (!o.is_number() || !(std::abs(o.get<double>()) <= kMaxProbeOrigin))
      grid.fail(fmt::format("'grid.origin' must be three numbers in [-{1}, {1}], not {0}",
                            ManifestFields::shown(origin), kMaxProbeOrigin));
    set.grid.origin[a] = float(o.get<double>());
  }
  set.grid.spacing = float(grid.number("spacing", 0.0, kMaxProbeSpacing, true));
  const uint64_t count = uint64_t(set.grid.count());
  manifest.expect_same("probes", manifest.integer("probes", 1, uint64_t{1} << 40), count,
                       "'grid.size'");
  // Checked against the records below, once they are read.
  const uint64_t valid = manifest.integer("valid", 0, count);
  if (manifest.file_name("data") != kDataFile)
    manifest.fail(fmt::format("'data' must be \"{}\", not {}", kDataFile,
                              ManifestFields::shown(manifest.at("data"))));
  const fs::path data_path = folder / kDataFile;
  const std::string dw = data_path.string();
  std::ifstream in(data_path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(fmt::format("{}: cannot open", dw));
  const uint64_t bytes = uint64_t(in.tellg());
  in.seekg(0);
  if (bytes < kHeaderBytes) throw Error(fmt::format("{}: truncated header", dw));
  char magic[8];
  uint32_t version = 0, floats = 0;
  uint64_t points = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&version), 4);
  in.read(reinterpret_cast<char*>(&floats), 4);
  in.read(reinterpret_cast<char*>(&points), 8);
  if (std::memcmp(magic, kMagic, 8) != 0 || version != kVersion || floats != kFloatsPerProbe)
    throw Error(fmt::format("{}: not an ILLUMPRB version {} file of {} floats per probe", dw,
                            kVersion, kFloatsPerProbe));
  if (points != uint64_t(set.grid.count()))
    throw Error(
        fmt::format("{}: holds {} probes, the grid needs {}", dw, points, set.grid.count()));
  const uint64_t expected = kHeaderBytes + points * sizeof(ProbeRecord);
  if (bytes != expected)
    throw Error(fmt::format("{}: {} bytes, {} expected ({})", dw, bytes, expected,
                            bytes < expected ? "truncated" : "trailing data"));
  set.probes.resize(points);
  in.read(reinterpret_cast<char*>(set.probes.data()),
          std::streamsize(points * sizeof(ProbeRecord)));
  if (!in) throw Error(fmt::format("{}: read error", dw));
  for (size_t p = 0; p < set.probes.size(); ++p) {
    const float* f = reinterpret_cast<const float*>(&set.probes[p]);
    for (uint32_t i = 0; i < kFloatsPerProbe; ++i)
      if (!std::isfinite(f[i]))
        throw Error(fmt::format("{}: value {} of probe {} is not finite", dw, i, p));
    const ProbeRecord& r = set.probes[p];
    if (r.weight != 0.0f && r.weight != 1.0f)
      throw Error(fmt::format("{}: probe {} has weight {} (0 or 1)", dw, p, r.weight));
    if (!(r.backface_fraction >= 0.0f && r.backface_fraction <= 1.0f))
      throw Error(fmt::format("{}: probe {} has back-face share {} (not in [0, 1])", dw, p,
                              r.backface_fraction));
  }
  uint64_t weighted = 0;
  for (const ProbeRecord& r : set.probes) weighted += r.weight > 0.0f ? 1 : 0;
  if (weighted != valid)
    manifest.fail(
        fmt::format("'valid' is {}, but {} holds {} valid probes", valid, kDataFile, weighted));
  return set;
}

void check_probe_scene(const Scene& scene, const ProbeSet& set) {
  const std::string where = set.folder.empty() ? "probe set" : set.folder;
  const Scene statics = static_part(scene);
  const std::string hash = geometry_hash_hex(statics);
  if (statics.triangle_count() != set.scene_triangles || hash != set.scene_hash)
    throw Error(fmt::format(
        "{}: baked for scene '{}' ({} triangles, hash {}), not for '{}' ({} triangles, hash {}); "
        "bake it again for this scene",
        where, set.scene, set.scene_triangles, set.scene_hash, scene.name, statics.triangle_count(),
        hash));
}

ProbeSet load_probe_set_for(const fs::path& folder, const Scene& scene) {
  ProbeSet set = load_probe_set(folder);
  check_probe_scene(scene, set);
  return set;
}

}  // namespace illum::baked
