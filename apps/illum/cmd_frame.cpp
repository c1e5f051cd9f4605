// `illum frame SCENE --technique forward -o frame.png`: one headless real-time frame on the
// Vulkan device (a GPU, or lavapipe on the CPU), with per-pass GPU milliseconds. With
// --frames N the frame is rendered W + N times and the median over the last N is printed.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "illum/core/log.h"
#include "illum/gpu/context.h"
#include "illum/realtime/baked_lightmap.h"
#include "illum/realtime/renderer.h"
#include "illum/scene/load.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

struct FrameArgs {
  std::string scene;
  std::string output;
  std::string technique = "forward";
  std::string shadows = "map";
  std::string tonemap = "aces";
  int width = 0, height = 0;
  int frames = 1, warmup = 0;
  std::string json;
  std::string device;
  std::string lightmap;  // folder written by `illum bake`
  float exposure = 1.0f;
  bool fixed_exposure = false;
  std::vector<std::string> params;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void run_frame(const FrameArgs& args) {
  if (!args.output.empty()) check_output_path(args.output);
  if (args.frames < 1) throw Error(fmt::format("--frames {} must be ≥ 1", args.frames));
  if (args.warmup < 0) throw Error(fmt::format("--warmup {} must be ≥ 0", args.warmup));

  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"technique", "--technique"},
                               {"shadows", "--shadows"},
                               {"tone_mapper", "--tonemap"},
                               {"width", "--width"},
                               {"height", "--height"},
                               {"exposure", "--exposure"}});
  Scene scene = load_scene(args.scene);
  realtime::Lightmap lightmap;
  if (!args.lightmap.empty())
    lightmap = realtime::prepare_lightmap_display(scene, atlas::load_lightmap_set(args.lightmap));
  if (!j.contains("ambient"))
    j["ambient"] = {scene.settings.ambient.r, scene.settings.ambient.g, scene.settings.ambient.b};
  j["technique"] = args.technique;
  j["shadows"] = args.shadows;
  j["tone_mapper"] = args.tonemap;
  j["width"] = args.width > 0 ? args.width : scene.settings.width;
  j["height"] = args.height > 0 ? args.height : scene.settings.height;
  j["exposure"] = args.exposure;
  if (args.fixed_exposure) j["auto_exposure"] = false;
  // Timing runs re-render the shadow maps every frame so their cost is in every median
  // (an interactive frame only re-renders them when lights change).
  if (args.frames > 1 && !j.contains("shadow_update_period")) j["shadow_update_period"] = 1;
  const Params params(j, "--param");
  const realtime::RendererOptions options = realtime::RendererOptions::from_params(params);
  params.check_all_used();

  gpu::ContextOptions context_options;
  context_options.device_filter = args.device;
  gpu::Context context(context_options);
  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  realtime::Renderer renderer(context, scene, options);
  if (lightmap.kind != realtime::LightmapKind::kNone) renderer.set_lightmap(lightmap);

  std::map<std::string, std::vector<double>> pass_ms;
  std::vector<std::string> order;
  std::vector<double> gpu_total, wall;
  for (int f = 0; f < args.warmup + args.frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render(camera);
    const auto t1 = std::chrono::steady_clock::now();
    if (f < args.warmup) continue;
    double total = 0.0;
    for (const gpu::PassTime& t : renderer.pass_times()) {
      if (!pass_ms.count(t.name)) order.push_back(t.name);
      pass_ms[t.name].push_back(t.ms);
      // CPU work is not GPU time, and nested scopes are inside their pass's.
      if (t.name.rfind("cpu:", 0) != 0 && t.depth == 0) total += t.ms;
    }
    gpu_total.push_back(total);
    wall.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }

  if (!args.output.empty()) {
    const ImageFormat format = image_format_from_path(args.output);
    if (format == ImageFormat::kExr || format == ImageFormat::kHdr)
      write_image(args.output, renderer.hdr());
    else
      write_image(args.output, renderer.ldr());
  }

  std::printf(
      "illum frame: %s, %dx%d, %s, shadows %s, device '%s'%s, %d frame(s) after %d warm-up\n",
      scene.name.c_str(), options.width, options.height, args.technique.c_str(),
      args.shadows.c_str(), context.device_name().c_str(),
      context.timestamps() ? "" : " (no timestamps)", args.frames, args.warmup);
  nlohmann::json passes = nlohmann::json::array();
  for (const std::string& name : order) {
    const auto& v = pass_ms.at(name);
    std::printf("  %-16s %9.4f ms%s\n", name.c_str(), median(v),
                static_cast<int>(v.size()) < args.frames
                    ? fmt::format("  (ran in {} of {} frames)", v.size(), args.frames).c_str()
                    : "");
    passes.push_back({{"name", name},
                      {"median_ms", median(v)},
                      {"runs", v.size()},
                      {"min_ms", *std::min_element(v.begin(), v.end())},
                      {"max_ms", *std::max_element(v.begin(), v.end())}});
  }
  std::printf(
      "  %-16s %9.4f ms (GPU, sum of passes)\n  %-16s %9.4f ms (CPU wall, submit to fence)\n",
      "frame", median(gpu_total), "wall", median(wall));
  if (!args.json.empty()) {
    nlohmann::json out = {{"scene", scene.name},
                          {"width", options.width},
                          {"height", options.height},
                          {"technique", args.technique},
                          {"shadows", args.shadows},
                          {"tonemap", args.tonemap},
                          {"device", context.device_name()},
                          {"frames", args.frames},
                          {"warmup", args.warmup},
                          {"triangles", scene.triangle_count()},
                          {"passes", passes},
                          {"frame_gpu_median_ms", median(gpu_total)},
                          {"frame_wall_median_ms", median(wall)},
                          {"validation_messages", context.validation_message_count()}};
    std::ofstream file(args.json);
    if (!file) throw Error(fmt::format("--json {}: cannot open for writing", args.json));
    file << out.dump(2) << "\n";
  }
  if (!args.output.empty()) std::printf("  wrote %s\n", args.output.c_str());
}

}  // namespace

void add_frame_command(CLI::App& app) {
  auto args = std::make_shared<FrameArgs>();
  auto* cmd =
      app.add_subcommand("frame", "Render a real-time (Vulkan) frame headless and time its passes");
  cmd->add_option("scene", args->scene, "scene file or built-in name")->required();
  cmd->add_option("-o,--output", args->output,
                  "output image: .png .jpg (tone-mapped) or .exr .hdr (linear)");
  cmd->add_option("-t,--technique", args->technique, "forward or deferred")
      ->check(CLI::IsMember({"forward", "deferred"}))
      ->capture_default_str();
  cmd->add_option("--shadows", args->shadows,
                  "none, map (PCF cube maps), vsm, volume (stencil; forward or deferred)")
      ->check(CLI::IsMember({"none", "map", "vsm", "volume"}))
      ->capture_default_str();
  cmd->add_option("--tonemap", args->tonemap, "clamp, reinhard, aces, agx")
      ->check(CLI::IsMember({"clamp", "reinhard", "aces", "agx"}))
      ->capture_default_str();
  cmd->add_option("--width", args->width, "width (default: scene settings)")
      ->transform(number(1, 16384));
  cmd->add_option("--height", args->height, "height (default: scene settings)")
      ->transform(number(1, 16384));
  cmd->add_option("--frames", args->frames, "frames to time (median reported)")
      ->transform(number(1, INT_MAX))
      ->capture_default_str();
  cmd->add_option("--warmup", args->warmup, "untimed frames first")
      ->transform(number(0, INT_MAX))
      ->capture_default_str();
  cmd->add_option("--json", args->json, "write the timings as JSON to this file");
  cmd->add_option("--device", args->device, "pick the Vulkan device whose name contains this");
  cmd->add_option("--lightmap", args->lightmap,
                  "show a light-map folder written by `illum bake` (replaces the lights it holds)");
  cmd->add_option("--exposure", args->exposure, "exposure multiplier")
      ->transform(number(0.0f, 1e6f))
      ->capture_default_str();
  cmd->add_flag("--fixed-exposure", args->fixed_exposure,
                "no auto-exposure from the log-average luminance");
  cmd->add_option(
      "-p,--param", args->params,
      "renderer option key=value (repeatable): shadow_resolution, pcf_taps, pcf_radius, "
      "shadow_bias, vsm_tau, shadow_update_period, volume_back_faces, silhouettes=gpu|cpu, "
      "half_lambert, ambient=[r,g,b] (default: the scene's settings.ambient), key, bloom_strength, "
      "bloom_threshold, "
      "deferred_lighting=compute|volumes");
  cmd->callback([args] { run_frame(*args); });
}

}  // namespace illum::cli
