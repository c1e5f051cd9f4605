// `illum relight SCENE --baked FOLDER (--sun X,Y,Z[,E] | --sky R,G,B|FILE) -o IMAGE`: renders baked
// PRT transfer (the folder of baked/prt_file.h, written by `illum bake --kind prt`,
// cmd_bake_prt.cpp) under a distant light (bake/prt_relight.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "baked_kind.h"
#include "commands.h"
#include "illum/bake/prt_relight.h"
#include "illum/baked/prt_file.h"
#include "illum/core/auto_exposure.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/core/tonemap.h"
#include "illum/render/render_setup.h"
#include "illum/scene/lighting_overrides.h"
#include "illum/scene/load.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct RelightArgs {
  std::string scene, prt, output, lookup = "texels", tonemap = "aces";
  LightingArgs lighting;  // --sun X,Y,Z[,E] or --sky: the one light of the transfer
  float rotate = 0.0f;
  float exposure = 1.0f;
  bool fixed_exposure = false;
  int width = 0, height = 0, spp = 4, threads = 0;
  LoadOptions load;
};

void run_relight(const RelightArgs& args) {
  check_output_path(args.output);
  require_baked_kind(args.prt, BakedKind::kPrt, "illum relight");
  const std::string& sun_text = args.lighting.sun;
  const std::string& sky_text = args.lighting.sky;
  if (sun_text.empty() == sky_text.empty())
    throw Error("relight: give exactly one light, --sun X,Y,Z[,E] or --sky R,G,B|FILE");
  const ToneMapper mapper = tone_mapper_from_string(args.tonemap);
  bake::RelightOptions options;
  if (args.lookup == "texels")
    options.lookup = bake::PrtLookup::kTexels;
  else if (args.lookup == "vertices")
    options.lookup = bake::PrtLookup::kVertices;
  else if (args.lookup == "vq")
    options.lookup = bake::PrtLookup::kVq;
  else
    throw Error(fmt::format("--lookup '{}': texels, vertices or vq", args.lookup));
  // The same --sun and --sky as every other command (scene/lighting_overrides.h), read
  // into a scene of their own.
  Scene light_scene;
  std::optional<vec3> sun;
  Color irradiance(kPi);
  if (!sun_text.empty()) {
    add_sun(light_scene, sun_text);
    sun = light_scene.lights.back().direction;
    irradiance = light_scene.lights.back().irradiance;
  }
  std::optional<Environment> env;
  if (!sky_text.empty()) {
    set_sky(light_scene, sky_text);
    env = std::move(*light_scene.environment);
    env->rotation_y = radians(args.rotate);
  }
  baked::PrtSet set = baked::load_prt_set(args.prt);
  const bake::ShLight light =
      sun ? bake::sun_light(set.bands, *sun, irradiance) : bake::environment_light(set.bands, *env);
  Scene scene = load_scene(args.scene, args.load);
  baked::apply_prt_set(scene, set);
  log::release();

  ThreadLimit limit(args.threads);
  const auto t0 = std::chrono::steady_clock::now();
  const RayTracer tracer(scene);
  options.width = args.width > 0 ? args.width : scene.settings.width;
  options.height = args.height > 0 ? args.height : scene.settings.height;
  options.samples = args.spp;
  options.threads = args.threads;
  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  const Image image = bake::relight(scene, tracer, set, light, camera, options);
  const double seconds = seconds_since(t0);
  const ImageFormat format = image_format_from_path(args.output);
  if (format == ImageFormat::kExr || format == ImageFormat::kHdr)
    write_image(args.output, image);
  else
    write_image(
        args.output,
        tone_mapped(image, mapper, display_exposure(image, args.exposure, args.fixed_exposure)));
  std::fprintf(stderr, "illum: relight %s, %d bands %s (%s), %dx%d %d spp in %.2fs -> %s\n",
               scene.name.c_str(), set.bands, bake::to_string(set.mode), args.lookup.c_str(),
               options.width, options.height, options.samples, seconds, args.output.c_str());
}

}  // namespace

void add_relight_command(CLI::App& app) {
  auto args = std::make_shared<RelightArgs>();
  auto* cmd = app.add_subcommand(
      "relight", "Render baked PRT transfer (illum bake --kind prt) under a sun or an environment");
  cmd->add_option("scene", args->scene, "the scene the folder was baked for")->required();
  cmd->add_option("--baked", args->prt, "PRT folder written by `illum bake --kind prt`")
      ->required();
  cmd->add_option("-o,--output", args->output, "output image (.png, .exr, .hdr, ...)")->required();
  add_lighting_options(cmd, &args->lighting);  // one of --sun or --sky
  cmd->add_option("--rotate", args->rotate, "turn the environment about +y by DEG degrees")
      ->transform(number(-36000.0f, 36000.0f));
  cmd->add_option(
         "--lookup", args->lookup,
         "texels (SHL-map, bilinear), vertices, or vq (the compressed map, 4 taps at ±¼ texel)")
      ->check(CLI::IsMember({"texels", "vertices", "vq"}))
      ->capture_default_str();
  cmd->add_option("--width", args->width, "image width (default: the scene's)")
      ->transform(number(1, 16384));
  cmd->add_option("--height", args->height, "image height (default: the scene's)")
      ->transform(number(1, 16384));
  cmd->add_option("--spp", args->spp, "primary rays per pixel")
      ->transform(number(1, 4096))
      ->capture_default_str();
  cmd->add_option("--exposure", args->exposure,
                  "8-bit output: a multiplier on the auto exposure (with --fixed-exposure, the "
                  "whole exposure)")
      ->transform(number(FLT_MIN, FLT_MAX))
      ->capture_default_str();
  cmd->add_flag("--fixed-exposure", args->fixed_exposure,
                "8-bit output: no auto exposure, --exposure alone scales the radiance");
  cmd->add_option("--tonemap", args->tonemap,
                  "tone mapper for 8-bit output: clamp, reinhard, aces, agx")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "worker threads (0: all cores)")
      ->transform(number(0, 4096));
  add_load_options(cmd, &args->load);
  cmd->callback([args] { run_relight(*args); });
}

}  // namespace illum::cli
