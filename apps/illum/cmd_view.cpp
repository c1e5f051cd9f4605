// `illum view SCENE`: the real-time renderer in a window (GLFW + Vulkan swapchain) with
// keyboard/mouse camera controls and an ImGui panel of every renderer parameter.
// --close-after-frames N / --close-after-seconds S close it, --screenshot writes the last frame and
// --camera-out the camera as left, as a scene file's "camera" object (tests, docs, scene
// authoring). Without a window (no display), it says so and renders one frame headless instead.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <system_error>

#include <unistd.h>

#include "baked_display.h"
#include "commands.h"
#include "illum/core/file_write.h"
#include "illum/core/log.h"
#include "illum/gpu/context.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/renderer_input.h"
#include "illum/realtime/viewer.h"
#include "illum/scene/load.h"
#include "option_checks.h"
#include "realtime_options.h"

namespace illum::cli {

namespace {

struct ViewArgs {
  std::string scene;
  RealtimeArgs realtime;
  int width = 1280, height = 720;
  std::string fallback_output = "view.png";
  int frames = 0;
  double seconds = 0.0;
  std::string screenshot;
  std::string camera_out;
  std::vector<std::string> baked;  // folders written by `illum bake` (baked_display.h)
  LoadOptions load;
  LightingArgs lighting;  // --sun, --sky
};

// One line of JSON, checked to the last byte and renamed into place (core/file_write.h).
void write_camera(const std::string& path, const Camera& camera) {
  write_file_atomically(path, realtime::camera_json(camera) + "\n");
}

void run_view(const ViewArgs& args) {
  check_output_path(args.fallback_output);
  if (!args.screenshot.empty()) {
    check_output_path(args.screenshot);
    if (image_format_from_path(args.screenshot) != ImageFormat::kPng)
      throw Error(fmt::format("--screenshot {}: must be a .png file", args.screenshot));
  }
  if (!args.camera_out.empty()) {
    const std::filesystem::path p(args.camera_out);
    if (p.extension() != ".json")
      throw Error(fmt::format("--camera-out {}: must be a .json file", args.camera_out));
    if (!p.parent_path().empty() && !std::filesystem::is_directory(p.parent_path()))
      throw Error(fmt::format("--camera-out {}: output folder '{}' does not exist", args.camera_out,
                              p.parent_path().string()));
  }
  if (args.frames < 0) throw Error(fmt::format("--close-after-frames {} must be ≥ 0", args.frames));
  if (!std::isfinite(args.seconds) || args.seconds < 0.0)
    throw Error(fmt::format("--close-after-seconds {} must be a finite number ≥ 0", args.seconds));
  Scene scene = load_scene(args.scene, args.load);
  apply_lighting_options(scene, args.lighting, "view", Unlit::kWarn, /*realtime=*/true);
  realtime::ViewerOptions viewer;
  const BakedDisplay baked = load_baked_display(scene, args.baked);
  viewer.lightmap = baked.lightmap;
  viewer.prt = baked.prt;
  realtime::RenderSettings settings = realtime_settings(args.realtime, scene, false);
  if (!baked.prt.empty() && !args.lighting.sun.empty())
    show_sun_on_prt(&settings, args.lighting.sun);
  settings.width = args.width;
  settings.height = args.height;
  if (baked.any()) settings.enable("baked");
  settings.check();
  std::string reason;
  viewer.frames = args.frames;
  viewer.seconds = args.seconds;
  viewer.screenshot = args.screenshot;
  Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  realtime::check_realtime_input(scene, settings.get<int>("lighting.single_light"));
  log::release();  // the input is checked: the load's warnings may show now
  if (!realtime::run_viewer(scene, settings, viewer, &camera, &reason)) {
    std::fprintf(stderr,
                 "illum view: no window available (%s); rendering one frame headless to %s\n",
                 reason.c_str(), args.fallback_output.c_str());
    gpu::Context context;
    realtime::Renderer renderer(context, scene, settings);
    baked.show(renderer);
    renderer.render(camera);
    write_image(args.fallback_output, renderer.ldr());
  }
  if (!args.camera_out.empty()) write_camera(args.camera_out, camera);
}

}  // namespace

void add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  auto* cmd =
      app.add_subcommand("view", "Open a window with the real-time renderer (headless fallback)");
  cmd->add_option("scene", args->scene, "scene file or built-in name")->required();
  add_realtime_options(cmd, &args->realtime);
  cmd->add_option("--width", args->width, "window width")
      ->transform(number(1, 16384))
      ->capture_default_str();
  cmd->add_option("--height", args->height, "window height")
      ->transform(number(1, 16384))
      ->capture_default_str();
  cmd->add_option("--fallback-output", args->fallback_output,
                  "image written when no window can be opened")
      ->capture_default_str();
  cmd->add_option("--close-after-frames", args->frames,
                  "close the window after N frames (0: run until closed)")
      ->transform(number(0, INT_MAX))
      ->capture_default_str();
  cmd->add_option("--close-after-seconds", args->seconds,
                  "close the window after S seconds (0: run until closed)")
      ->transform(number(0.0, 1e7))
      ->capture_default_str();
  cmd->add_option("--screenshot", args->screenshot,
                  "write the last presented frame, panel included, to this .png");
  add_baked_option(cmd, &args->baked);
  cmd->add_option("--camera-out", args->camera_out,
                  "at exit, write the camera as one line of JSON to this .json file: the "
                  "scene file's \"camera\" object (position, look_at, up, fov_y_deg), to "
                  "paste into a .illum.json (the C key prints it while running)");
  add_load_options(cmd, &args->load);
  add_lighting_options(cmd, &args->lighting);
  cmd->callback([args] { run_view(*args); });
}

}  // namespace illum::cli
