// `illum view SCENE`: the real-time renderer in a window (GLFW + Vulkan swapchain) with
// keyboard/mouse camera controls and an ImGui panel of every renderer parameter.
// --frames N closes it after N frames and --screenshot writes the last one (tests, docs).
// Without a window (no display), it says so and renders one frame headless instead.
#include <cstdio>
#include <memory>

#include "commands.h"
#include "illum/gpu/context.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/viewer.h"
#include "illum/scene/load.h"

namespace illum::cli {

namespace {

struct ViewArgs {
  std::string scene;
  std::string technique = "forward";
  std::string shadows = "map";
  std::string tonemap = "aces";
  int width = 1280, height = 720;
  std::string fallback_output = "view.png";
  int frames = 0;
  std::string screenshot;
};

void run_view(const ViewArgs& args) {
  check_output_path(args.fallback_output);
  if (!args.screenshot.empty()) {
    check_output_path(args.screenshot);
    if (image_format_from_path(args.screenshot) != ImageFormat::kPng)
      throw Error(fmt::format("--screenshot {}: must be a .png file", args.screenshot));
  }
  if (args.frames < 0) throw Error(fmt::format("--frames {} must be ≥ 0", args.frames));
  const Scene scene = load_scene(args.scene);
  realtime::RendererOptions options;
  options.width = args.width;
  options.height = args.height;
  options.technique = realtime::technique_from_string(args.technique);
  options.shadows = realtime::shadow_mode_from_string(args.shadows);
  options.tone_mapper = realtime::tone_map_op_from_string(args.tonemap);
  std::string reason;
  realtime::ViewerOptions viewer;
  viewer.frames = args.frames;
  viewer.screenshot = args.screenshot;
  if (realtime::run_viewer(scene, options, viewer, &reason)) return;
  std::fprintf(stderr, "illum view: no window available (%s); rendering one frame headless to %s\n",
               reason.c_str(), args.fallback_output.c_str());
  gpu::Context context;
  realtime::Renderer renderer(context, scene, options);
  renderer.render(scene.camera ? *scene.camera : Camera::framing(scene.bounds()));
  write_image(args.fallback_output, renderer.ldr());
}

}  // namespace

void add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  auto* cmd =
      app.add_subcommand("view", "Open a window with the real-time renderer (headless fallback)");
  cmd->add_option("scene", args->scene, "scene file or built-in name")->required();
  cmd->add_option("-t,--technique", args->technique, "forward or deferred")
      ->check(CLI::IsMember({"forward", "deferred"}))
      ->capture_default_str();
  cmd->add_option("--shadows", args->shadows, "none, map, vsm, volume")
      ->check(CLI::IsMember({"none", "map", "vsm", "volume"}))
      ->capture_default_str();
  cmd->add_option("--tonemap", args->tonemap, "clamp, reinhard, aces, agx")
      ->check(CLI::IsMember({"clamp", "reinhard", "aces", "agx"}))
      ->capture_default_str();
  cmd->add_option("--width", args->width, "window width")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--height", args->height, "window height")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--fallback-output", args->fallback_output,
                  "image written when no window can be opened")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "close the window after N frames (0: run until closed)")
      ->capture_default_str();
  cmd->add_option("--screenshot", args->screenshot,
                  "write the last presented frame, panel included, to this .png");
  cmd->callback([args] { run_view(*args); });
}

}  // namespace illum::cli
