// `illum frame SCENE --technique forward -o frame.png`: one headless real-time frame on the
// Vulkan device (a GPU, or lavapipe on the CPU), with per-pass GPU milliseconds. With
// --frames N the frame is rendered W + N times and the median over the last N is printed.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "baked_display.h"
#include "commands.h"
#include "illum/core/file_write.h"
#include "illum/core/log.h"
#include "illum/core/progress.h"
#include "illum/gpu/allocator.h"
#include "illum/gpu/context.h"
#include "illum/gpu/gpu_image.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/technique_registry.h"
#include "illum/scene/load.h"
#include "option_checks.h"
#include "realtime_options.h"

namespace illum::cli {

namespace {

struct FrameArgs {
  std::string scene;
  std::string output;
  RealtimeArgs realtime;
  int width = 0, height = 0;
  int frames = 1, warmup = 0;
  std::string json;
  bool json_given = false;  // --json without a file: with --list, JSON on stdout
  std::string device;
  std::vector<std::string> baked;  // folders written by `illum bake` (baked_display.h)
  bool list = false;
  LoadOptions load;
  LightingArgs lighting;  // --sun, --sky
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// `illum frame --list [--json [FILE]]`: every registered technique and its parameters.
// Needs no scene and creates no Vulkan instance.
void list_techniques(const FrameArgs& args) {
  if (!args.json_given) {
    std::fputs(realtime::technique_listing().c_str(), stdout);
    return;
  }
  const std::string text = realtime::technique_listing_json().dump(2) + "\n";
  if (args.json.empty()) {
    std::fputs(text.c_str(), stdout);
    return;
  }
  check_writable_output(args.json);
  write_file_atomically(args.json, text);
}

void run_frame(const FrameArgs& args) {
  if (args.list) {
    if (!args.scene.empty() || !args.output.empty())
      throw Error("--list prints the techniques and renders nothing: give no scene or -o");
    list_techniques(args);
    return;
  }
  if (args.scene.empty()) throw Error("scene is required (or --list)");
  if (args.json_given && args.json.empty())
    throw Error("--json needs a file name (only --list --json prints to stdout)");
  // Every output is checked before any is written: a bad --json leaves no image behind.
  if (!args.output.empty()) check_output_path(args.output);
  if (!args.json.empty()) check_writable_output(args.json);
  if (args.frames < 1) throw Error(fmt::format("--frames {} must be ≥ 1", args.frames));
  if (args.warmup < 0) throw Error(fmt::format("--warmup {} must be ≥ 0", args.warmup));

  Scene scene = load_scene(args.scene, args.load);
  apply_lighting_options(scene, args.lighting, "frame", Unlit::kWarn, /*realtime=*/true);
  const BakedDisplay baked = load_baked_display(scene, args.baked);
  realtime::RenderSettings settings = realtime_settings(args.realtime, scene, args.frames > 1);
  if (!baked.prt.empty() && !args.lighting.sun.empty())
    show_sun_on_prt(&settings, args.lighting.sun);
  settings.width = args.width > 0 ? args.width : scene.settings.width;
  settings.height = args.height > 0 ? args.height : scene.settings.height;
  if (baked.any()) settings.enable("baked");
  settings.check();

  gpu::ContextOptions context_options;
  context_options.device_filter = args.device;
  gpu::Context context(context_options);
  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  realtime::Renderer renderer(context, scene, settings);
  baked.show(renderer);
  log::release();  // the input is checked: the load's warnings may show now

  std::map<std::string, std::vector<double>> pass_ms;
  std::map<std::string, int> depth;  // nested scopes (per-light steps) print indented
  std::vector<std::string> order;
  std::vector<double> gpu_total, wall;
  Progress progress("frame", args.warmup + args.frames, args.warmup + args.frames > 1);
  for (int f = 0; f < args.warmup + args.frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render(camera);
    const auto t1 = std::chrono::steady_clock::now();
    progress.advance();
    if (f < args.warmup) continue;
    double total = 0.0;
    for (const gpu::PassTime& t : renderer.pass_times()) {
      if (!pass_ms.count(t.name)) {
        order.push_back(t.name);
        depth[t.name] = t.depth;
      }
      pass_ms[t.name].push_back(t.ms);
      // CPU work is not GPU time, and nested scopes are inside their pass's.
      if (t.name.rfind("cpu:", 0) != 0 && t.depth == 0) total += t.ms;
    }
    gpu_total.push_back(total);
    wall.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  progress.finish();

  if (!args.output.empty()) {
    const ImageFormat format = image_format_from_path(args.output);
    if (format == ImageFormat::kExr || format == ImageFormat::kHdr)
      write_image(args.output, renderer.hdr());
    else
      write_image(args.output, renderer.ldr());
  }
  // With --json, one more (untimed) frame after the image is written: the work of each pass
  // (its raster fills, stencil overdraw counted by occlusion queries, compute bytes), which
  // `illum-bench raster` sets against the device's bounds.
  std::map<std::pair<std::string, int>, nlohmann::json> work;
  if (!args.json.empty())
    for (const gpu::PassTime& t : renderer.measure_work(camera)) {
      if (t.fills.empty() && t.bytes <= 0.0 && t.triangles <= 0.0) continue;
      nlohmann::json fills = nlohmann::json::array();
      for (const auto& [f, count] : t.fills) {
        nlohmann::json colors = nlohmann::json::array();
        for (VkFormat c : f.colors)
          colors.push_back({{"format", c}, {"name", gpu::format_name(c)}});
        fills.push_back({{"key", f.key()},
                         {"width", f.width},
                         {"height", f.height},
                         {"colors", colors},
                         {"depth_format", f.depth_format},
                         {"depth", static_cast<int>(f.depth)},
                         {"blend", f.blend},
                         {"uncleared", f.uncleared},
                         {"count", count}});
      }
      work[{t.name, t.depth}] = {{"fills", fills}, {"bytes", t.bytes}, {"triangles", t.triangles}};
      if (t.rasterized >= 0.0) work[{t.name, t.depth}]["rasterized_triangles"] = t.rasterized;
      if (t.vertices >= 0.0) work[{t.name, t.depth}]["vertex_invocations"] = t.vertices;
      if (t.clusters >= 0.0) work[{t.name, t.depth}]["clusters"] = t.clusters;
      if (t.quads >= 0.0) {
        work[{t.name, t.depth}]["quads"] = t.quads;
        work[{t.name, t.depth}]["quad_samples"] = t.quad_samples;
      }
    }

  // And the shading bound of the fragment lighting pass (forward): its lighting as one
  // full-screen pass over a G-buffer of the same view, timed as often as the frames (3 to 50
  // times), which `illum-bench raster` scales by the pass's quads.
  realtime::ShadingTime shading;
  const bool shading_measured =
      !args.json.empty() && context.timestamps() &&
      renderer.measure_shading(camera, std::clamp(args.frames, 3, 50), &shading);
  if (shading_measured) {
    auto w = work.find({shading.pass, 0});
    if (w != work.end())
      w->second["shading"] = {{"runs_ms", shading.runs_ms}, {"median_ms", median(shading.runs_ms)},
                              {"pixels", shading.pixels},   {"input_bytes", shading.input_bytes},
                              {"width", shading.width},     {"height", shading.height}};
  }

  std::printf(
      "illum frame: %s, %dx%d, %s, shadows %s, device '%s'%s, %d frame(s) after %d warm-up\n",
      scene.name.c_str(), settings.width, settings.height, settings.pipeline.c_str(),
      settings.shadows.c_str(), context.device_name().c_str(),
      context.timestamps() ? "" : " (no timestamps)", args.frames, args.warmup);
  nlohmann::json passes = nlohmann::json::array();
  for (const std::string& name : order) {
    const auto& v = pass_ms.at(name);
    const int d = depth.at(name);
    std::printf("  %*s%-*s %9.4f ms%s\n", 2 * d, "", 16 - 2 * d, name.c_str(), median(v),
                static_cast<int>(v.size()) < args.frames
                    ? fmt::format("  (ran in {} of {} frames)", v.size(), args.frames).c_str()
                    : "");
    passes.push_back({{"name", name},
                      {"depth", d},
                      {"median_ms", median(v)},
                      {"runs", v.size()},
                      {"min_ms", *std::min_element(v.begin(), v.end())},
                      {"max_ms", *std::max_element(v.begin(), v.end())}});
    if (const auto w = work.find({name, d}); w != work.end()) passes.back()["work"] = w->second;
  }
  std::printf(
      "  %-16s %9.4f ms (GPU, sum of passes)\n  %-16s %9.4f ms (CPU wall, submit to fence)\n",
      "frame", median(gpu_total), "wall", median(wall));
  if (shading_measured)
    std::printf("  %-16s %9.4f ms (%s's lighting, full screen over %.0f covered pixels)\n",
                "shading bound", median(shading.runs_ms), shading.pass.c_str(), shading.pixels);
  if (!args.json.empty()) {
    nlohmann::json out = {{"scene", scene.name},
                          {"width", settings.width},
                          {"height", settings.height},
                          {"technique", settings.pipeline},
                          {"shadows", settings.shadows},
                          {"techniques", settings.active_techniques()},
                          {"tonemap", settings.get<std::string>("tonemap.operator")},
                          {"device", context.device_name()},
                          {"driver", context.driver()},
                          {"frames", args.frames},
                          {"warmup", args.warmup},
                          {"triangles", scene.triangle_count()},
                          {"passes", passes},
                          {"frame_gpu_median_ms", median(gpu_total)},
                          {"frame_wall_median_ms", median(wall)},
                          {"validation_messages", context.validation_message_count()}};
    // Where the frame's memory went: dedicated allocations are the images the driver asked
    // to have memory of their own (and requests over a quarter block).
    const gpu::AllocatorStats memory = context.allocator().stats();
    out["gpu_memory"] = {{"blocks", memory.blocks},
                         {"dedicated", memory.dedicated},
                         {"reserved_bytes", memory.reserved_bytes},
                         {"used_bytes", memory.used_bytes}};
    write_file_atomically(args.json, out.dump(2) + "\n");
  }
  if (!args.output.empty()) std::printf("  wrote %s\n", args.output.c_str());
}

}  // namespace

void add_frame_command(CLI::App& app) {
  auto args = std::make_shared<FrameArgs>();
  auto* cmd =
      app.add_subcommand("frame", "Render a real-time (Vulkan) frame headless and time its passes");
  cmd->add_option("scene", args->scene, "scene file or built-in name (required but with --list)");
  cmd->add_option("-o,--output", args->output,
                  "output image: .png .jpg (tone-mapped) or .exr .hdr (linear)");
  add_realtime_options(cmd, &args->realtime);
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
  // The value is optional for `--list --json` (JSON on stdout); an empty one is refused.
  cmd->add_option("--json", args->json,
                  "write the timings as JSON to this file (with --list: the techniques, to this "
                  "file or stdout)")
      ->expected(0, 1)
      ->check(CLI::Validator(
          [](std::string& text) { return text.empty() ? std::string("needs a value") : ""; }, "",
          "non-empty"));
  cmd->add_flag("--list", args->list,
                "list every technique and its parameters (type, default, range, help) and exit; "
                "needs no scene or GPU");
  cmd->add_option("--device", args->device, "pick the Vulkan device whose name contains this");
  add_baked_option(cmd, &args->baked);
  add_load_options(cmd, &args->load);
  add_lighting_options(cmd, &args->lighting);
  cmd->callback([args, cmd] {
    args->json_given = cmd->count("--json") > 0;
    run_frame(*args);
  });
}

}  // namespace illum::cli
