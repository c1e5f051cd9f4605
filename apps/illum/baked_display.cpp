#include "baked_display.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "baked_kind.h"
#include "illum/bake/probe_lookup.h"
#include "illum/baked/lightmap_file.h"
#include "illum/baked/probe_file.h"
#include "illum/baked/prt_file.h"
#include "illum/core/error.h"
#include "illum/realtime/baked_lightmap.h"

namespace illum::cli {

namespace {

// The set's transfer in the renderer's order: vertices per mesh (the GPU vertex buffer's
// order) rather than per instance; apply_prt_set made every instance's mesh its own.
realtime::PrtTransfer prt_transfer(const Scene& scene, baked::PrtSet set) {
  realtime::PrtTransfer prt;
  prt.bands = set.bands;
  prt.width = set.atlas.width;
  prt.height = set.atlas.height;
  prt.texels = std::move(set.texel_transfer.data);
  prt.vq_representatives = std::move(set.vq.representatives);
  prt.vq_indices = std::move(set.vq.indices);
  if (!set.vertex_transfer.empty()) {
    const size_t channels = static_cast<size_t>(prt.channels());
    std::vector<size_t> first(scene.meshes.size() + 1, 0);
    for (size_t m = 0; m < scene.meshes.size(); ++m)
      first[m + 1] = first[m] + scene.meshes[m].vertex_count() * channels;
    prt.vertices.assign(first.back(), 0.0f);  // a mesh no instance draws: never shown
    for (size_t i = 0; i < scene.instances.size(); ++i) {
      const size_t m = static_cast<size_t>(scene.instances[i].mesh);
      std::copy(set.vertex_transfer[i].begin(), set.vertex_transfer[i].end(),
                prt.vertices.begin() + static_cast<std::ptrdiff_t>(first[m]));
    }
  }
  return prt;
}

// The set's grid, irradiance coefficients and validity weights as the renderer reads them
// (realtime/probe_volume.h), for the instances `scene` marks dynamic.
realtime::ProbeVolume probe_volume(const baked::ProbeSet& set, const Scene& scene) {
  static_assert(realtime::kProbeFloats == bake::kProbeVolumeFloats);
  realtime::ProbeVolume volume;
  volume.size = set.grid.size;
  volume.origin = set.grid.origin;
  volume.spacing = vec3(set.grid.spacing);
  volume.probes = bake::probe_volume_data(set.probes);
  volume.instances = bake::dynamic_instances(scene);
  return volume;
}

// The light-map the scene file carries (illum's .glb export, scene.h: SceneLightmap), shown
// as a plain folder's layer: its uv1 came with the meshes, so only the lights it holds leave
// the scene (area lights always; punctual ones the file marks illum_baked).
realtime::Lightmap embedded_lightmap(Scene& scene) {
  const SceneLightmap& map = *scene.lightmap;
  const std::string& file = scene.source_path;
  if (map.tone != "none")
    throw Error(fmt::format(
        "{}: its light-map holds display values (exported with --tone {}), not light; export "
        "it with --tone none to show it",
        file, map.tone));
  if (map.image.empty()) throw Error(fmt::format("{}: its light-map image was not read", file));
  for (const Instance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[static_cast<size_t>(instance.mesh)];
    if (mesh.uv1.size() != mesh.positions.size())
      throw Error(fmt::format("{}: mesh '{}' has no TEXCOORD_1, where its light-map is read", file,
                              mesh.name));
  }
  std::erase_if(scene.lights, [](const Light& light) {
    return light.type == LightType::kArea || light.in_lightmap;
  });
  realtime::Lightmap lightmap;
  lightmap.kind = realtime::LightmapKind::kPlain;
  lightmap.layers = {map.image};
  return lightmap;
}

}  // namespace

void BakedDisplay::show(realtime::Renderer& renderer) const {
  if (lightmap.kind != realtime::LightmapKind::kNone) renderer.set_lightmap(lightmap);
  if (!prt.empty()) renderer.set_prt(prt);
  if (!probes.empty()) renderer.set_probe_volume(probes);
}

BakedDisplay load_baked_display(Scene& scene, const std::vector<std::string>& folders) {
  // Every folder is told and read before the scene changes: a refusal leaves it as it was.
  std::vector<std::pair<const BakedKindInfo*, std::string>> chosen;
  for (const std::string& folder : folders) {
    const BakedKindInfo& kind = baked_folder_kind(folder);
    for (const auto& [other, other_folder] : chosen)
      if (other->kind == kind.kind)
        throw Error(fmt::format("--baked {}: a second {} folder ({} is one); show one of each kind",
                                folder, kind.name, other_folder));
    chosen.emplace_back(&kind, folder);
  }
  const auto given = [&](BakedKind kind) -> const std::string* {
    for (const auto& [k, folder] : chosen)
      if (k->kind == kind) return &folder;
    return nullptr;
  };
  const std::string* lightmap = given(BakedKind::kLightmap);
  const std::string* prt = given(BakedKind::kPrt);
  if (lightmap && prt)
    throw Error(fmt::format(
        "--baked {} (light-map) and --baked {} (PRT): each puts its own atlas on uv1 and "
        "holds the static surfaces' light; show one of them",
        *lightmap, *prt));

  BakedDisplay display;
  // Probes first: they were baked for the scene's static part as loaded, before any atlas
  // (which changes the meshes the geometry hash covers) is put on it.
  if (const std::string* probes = given(BakedKind::kProbes)) {
    display.probes = probe_volume(baked::load_probe_set_for(*probes, scene), scene);
    if (display.probes.empty())
      throw Error(
          fmt::format("--baked {}: probes light only meshes marked \"dynamic\": true, and "
                      "scene '{}' marks none",
                      *probes, scene.name));
  }
  if (lightmap) {
    const baked::LightmapSet set = baked::load_lightmap_set(*lightmap);
    baked::require_lightmap_layers(set, "show");
    display.lightmap = realtime::prepare_lightmap_display(scene, set);
  } else if (!prt && scene.lightmap) {
    display.lightmap = embedded_lightmap(scene);  // a folder given wins over the file's map
  }
  if (prt) {
    baked::PrtSet set = baked::load_prt_set(*prt);
    baked::apply_prt_set(scene, set);
    // The transfer holds the light of the add-on's sun (direct and bounced): the scene's own
    // lights would count it twice. Emitters still glow through their materials.
    scene.lights.clear();
    display.prt = prt_transfer(scene, std::move(set));
  }
  return display;
}

}  // namespace illum::cli
