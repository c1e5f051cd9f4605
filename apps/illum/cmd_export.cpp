// `illum export SCENE --baked DIR -o OUT.glb`: the scene as glTF 2.0 binary whose meshes
// carry the baked light-map's uv1 in TEXCOORD_1 and whose materials reference the map
// (RGBM PNG, MSFT_lightmap), plus the linear OUT.lightmap.exr (export/lightmap_export.h).
// Every input is checked before anything is written: the output's folder and name, --tone,
// the folder (baked/lightmap_file.h), and that it was baked for this scene.
#include <cstdio>
#include <memory>

#include "baked_kind.h"
#include "commands.h"
#include "illum/baked/lightmap_file.h"
#include "illum/core/log.h"
#include "illum/export/lightmap_export.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

struct ExportArgs {
  std::string scene, lightmap, output;
  exporter::LightmapExportOptions options;
  LoadOptions load;
};

void run_export(const ExportArgs& args) {
  exporter::check_export_output(args.output);
  exporter::check_export_options(args.options);
  require_baked_kind(args.lightmap, BakedKind::kLightmap, "illum export");
  const baked::LightmapSet set = baked::load_lightmap_set(args.lightmap);
  baked::require_lightmap_layers(set, "export");
  Scene scene = load_scene(args.scene, args.load);
  const exporter::LightmapExportResult r =
      exporter::export_gltf_with_lightmap(scene, set, args.output, args.options);
  log::release();
  std::printf(
      "wrote %s (%zu bytes: %zu meshes, %zu nodes, %zu materials, %zu textures, %zu "
      "lights, %s camera)\n",
      r.glb.string().c_str(), r.glb_bytes, r.gltf.meshes, r.gltf.nodes, r.gltf.materials,
      r.gltf.textures, r.gltf.lights, r.gltf.camera ? "a" : "no");
  std::printf(
      "light-map %dx%d: %s; RGBM PNG %zu bytes, range %g, tone %s (MSFT_lightmap, "
      "TEXCOORD_1); linear EXR %s\n",
      r.width, r.height, r.layer.c_str(), r.png_bytes, r.rgbm_range, args.options.tone.c_str(),
      r.exr.string().c_str());
  for (const std::string& dropped : r.gltf.dropped)
    std::printf("not exported: %s\n", dropped.c_str());
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand(
      "export",
      "Write a scene and its baked light-map as glTF 2.0 binary (TEXCOORD_1 + MSFT_lightmap, "
      "RGBM PNG) with the linear light-map EXR beside it");
  cmd->add_option("scene", args->scene,
                  "scene file (.obj, .gltf, .glb, .illum.json) or built-in name")
      ->required();
  cmd->add_option("--baked", args->lightmap, "light-map folder written by `illum bake`")
      ->required();
  cmd->add_option("-o,--output", args->output,
                  "OUT.glb (OUT.lightmap.exr is written beside it; an earlier pair is replaced)")
      ->required();
  cmd->add_option("--tone", args->options.tone,
                  "none (the PNG holds the linear map, RGBM) or lrp97 (LRP97 histogram tone "
                  "reproduction for 8-bit use; the EXR stays linear)")
      ->check(CLI::IsMember({"none", "lrp97"}))
      ->capture_default_str();
  cmd->add_option("--rgbm-range", args->options.rgbm_range,
                  "RGBM range M (0: the map's largest value, so nothing clamps; 1 with lrp97)")
      ->transform(number(0.0f, 1e30f))
      ->capture_default_str();
  add_load_options(cmd, &args->load);
  cmd->callback([args] { run_export(*args); });
}

}  // namespace illum::cli
