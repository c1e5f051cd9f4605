// `illum render SCENE --integrator NAME -o out.{png,jpg,exr,hdr}`: offline rendering.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "illum/core/auto_exposure.h"
#include "illum/core/interrupt.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/core/tonemap.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "job_role.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

struct RenderArgs {
  std::string scene;
  std::string integrator = "path";
  std::string output;
  int width = 0, height = 0, spp = 0;  // 0: from the scene's settings
  uint64_t seed = 0;
  int threads = 0;
  double seconds = 0.0;
  std::vector<std::string> params;  // key=value
  int bounces = -1;                 // -1: the integrator's default
  std::string bounce_mode;          // path: all, direct, indirect1
  std::string shadow_rays;          // whitted: on, off
  float exposure = 1.0f;
  bool fixed_exposure = false;
  std::string tonemap;    // empty: aces, or clamp for the views that are not radiance
  LightingArgs lighting;  // --sun, --sky
  bool no_preview = false;
  LoadOptions load;
};

// The integrator key each dedicated option sets, per integrator; an option given to an
// integrator without the key is refused rather than ignored.
struct OptionKey {
  const char* option;
  const char* integrator;
  const char* key;
};
constexpr OptionKey kOptionKeys[] = {
    {"--bounces", "path", "max_bounces"}, {"--bounces", "whitted", "max_depth"},
    {"--bounces", "photon", "max_depth"}, {"--bounces", "sppm", "max_depth"},
    {"--bounce-mode", "path", "bounces"}, {"--shadow-rays", "whitted", "shadows"},
};

Params integrator_params(const RenderArgs& args) {
  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"max_bounces", "--bounces"},
                               {"max_depth", "--bounces"},
                               {"bounces", "--bounce-mode"},
                               {"shadows", "--shadow-rays"}});
  const auto set = [&](const char* option, const nlohmann::json& value) {
    for (const OptionKey& k : kOptionKeys)
      if (option == std::string(k.option) && args.integrator == k.integrator) {
        j[k.key] = value;
        return;
      }
    throw Error(fmt::format("{} does not apply to -i {}", option, args.integrator));
  };
  if (args.bounces >= 0) set("--bounces", args.bounces);
  if (!args.bounce_mode.empty()) set("--bounce-mode", args.bounce_mode);
  if (!args.shadow_rays.empty()) set("--shadow-rays", args.shadow_rays == "on");
  Params params(j, "--param");
  params.unlist({"max_bounces", "max_depth", "bounces", "shadows"});
  return params;
}

// "out.exr" → "out.png": the tone-mapped preview written beside an HDR output.
std::string preview_path(const std::string& output) {
  return std::filesystem::path(output).replace_extension(".png").string();
}

void run_render(const RenderArgs& args) {
  check_output_path(args.output);
  refuse_with_several_ranks(args.seconds > 0.0, fmt::format("--time {}", args.seconds),
                            "the samples taken in the time would depend on the ranks; give "
                            "--spp instead");
  refuse_with_several_ranks(args.integrator == "sppm", "--integrator sppm",
                            "its photon passes update every pixel in turn");
  const ImageFormat format = image_format_from_path(args.output);
  const bool hdr_output = format == ImageFormat::kExr || format == ImageFormat::kHdr;
  // A folder where an output file goes would only fail after the render.
  for (const std::string& path :
       {args.output, hdr_output && !args.no_preview ? preview_path(args.output) : std::string()})
    if (!path.empty() && std::filesystem::is_directory(path))
      throw Error(fmt::format("{}: is a folder, not an image file", path));
  // Normals, albedo, depth and AO are values in [0, 1], not radiance: shown as they are.
  const bool radiance = args.integrator != "normals" && args.integrator != "albedo" &&
                        args.integrator != "depth" && args.integrator != "ao";
  const ToneMapper mapper = tone_mapper_from_string(!args.tonemap.empty() ? args.tonemap
                                                    : radiance            ? "aces"
                                                                          : "clamp");
  if (!(args.exposure > 0.0f) || !std::isfinite(args.exposure))
    throw Error(fmt::format("--exposure {} must be a positive number", args.exposure));

  Scene scene = load_scene(args.scene, args.load);
  add_sun_and_sky(scene, args.lighting);  // the integrators warn when nothing lights it
  RenderOptions options;
  options.width = args.width > 0 ? args.width : scene.settings.width;
  options.height = args.height > 0 ? args.height : scene.settings.height;
  options.spp = args.spp > 0 ? args.spp : scene.settings.spp;
  options.seed = args.seed;
  options.threads = threads_for_this_rank(args.threads);
  options.time_budget_s = args.seconds;

  Params params = integrator_params(args);
  auto integrator = Integrator::create(args.integrator, params);
  params.check_all_used();  // a --param the integrator did not read is a typo
  log::release();           // the input is checked: the load's warnings may show now

  ThreadLimit limit(options.threads);
  const auto t0 = std::chrono::steady_clock::now();
  const RayTracer tracer(scene);
  const auto t1 = std::chrono::steady_clock::now();
  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  const Image image = integrator->render(tracer, camera, options);
  const auto t2 = std::chrono::steady_clock::now();
  if (!writes_output()) return;  // rank 0 of the MPI job holds the image
  stop_if_interrupted();
  const float exposure = display_exposure(image, args.exposure, args.fixed_exposure || !radiance);

  if (hdr_output) {
    write_image(args.output, image);
    if (!args.no_preview) {
      // The pair is written whole or not at all: a preview that cannot be written takes
      // the linear file just written with it (a failed run leaves no output).
      try {
        // Until the preview is written too, a second Ctrl-C takes the linear file with it.
        const StagingPath pending(args.output);
        write_image(preview_path(args.output), tone_mapped(image, mapper, exposure));
      } catch (...) {
        std::error_code ec;
        std::filesystem::remove(args.output, ec);
        throw;
      }
    }
  } else {
    write_image(args.output, tone_mapped(image, mapper, exposure));
  }
  const double build_s = std::chrono::duration<double>(t1 - t0).count();
  const double render_s = std::chrono::duration<double>(t2 - t1).count();
  std::fprintf(stderr, "illum: %s %dx%d, %s: BVH %.2fs, render %.2fs -> %s%s\n",
               args.integrator.c_str(), options.width, options.height, scene.name.c_str(), build_s,
               render_s, args.output.c_str(),
               hdr_output && !args.no_preview ? (" + " + preview_path(args.output)).c_str() : "");
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Render a scene offline with a CPU integrator");
  cmd->add_option("scene", args->scene,
                  "scene file (.obj, .gltf, .glb, .illum.json) or built-in name")
      ->required();
  cmd->add_option("-i,--integrator", args->integrator, "integrator")
      ->check(CLI::IsMember(Integrator::names()))
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output,
                  "output image: .png .jpg (tone-mapped) or .exr .hdr (linear)")
      ->required();
  cmd->add_option("--width", args->width, "image width (default: scene settings)")
      ->transform(number(1, kMaxImageSide));
  cmd->add_option("--height", args->height, "image height (default: scene settings)")
      ->transform(number(1, kMaxImageSide));
  cmd->add_option("--spp", args->spp, "samples per pixel (default: scene settings)")
      ->transform(number(1, 1 << 24));
  cmd->add_option("--seed", args->seed,
                  "random seed (same seed: same image, whatever the thread count)")
      ->transform(number<uint64_t>(0, UINT64_MAX));
  cmd->add_option("--threads", args->threads,
                  "worker threads (0: all cores; under mpirun the node's cores over its ranks)")
      ->transform(number(0, 4096));
  cmd->add_option("--time", args->seconds,
                  "time budget in seconds for progressive integrators (0: none)")
      ->transform(number(0.0, 1e7));
  cmd->add_option("-p,--param", args->params, "integrator parameter key=value (repeatable)");
  cmd->add_option("--bounces", args->bounces,
                  "longest path in bounces (path: max_bounces, default 8; whitted: max_depth, "
                  "default 5; photon, sppm: max_depth, default the scene's max_bounces)")
      ->transform(number(0, 1024));
  cmd->add_option("--bounce-mode", args->bounce_mode,
                  "path: which light paths count (direct: one bounce only, indirect1: the "
                  "second only)")
      ->check(CLI::IsMember({"all", "direct", "indirect1"}));
  cmd->add_option("--shadow-rays", args->shadow_rays, "whitted: trace shadow rays")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--exposure", args->exposure,
                  "8-bit output: a multiplier on the auto exposure (with --fixed-exposure, and "
                  "for normals, albedo, depth and ao, the whole exposure)")
      ->transform(number(0.0f, 1e6f))
      ->capture_default_str();
  cmd->add_flag("--fixed-exposure", args->fixed_exposure,
                "8-bit output: no auto exposure, --exposure alone scales the radiance");
  cmd->add_option("--tonemap", args->tonemap,
                  "tone mapper for 8-bit output: clamp, reinhard, aces, agx (default aces; "
                  "clamp for normals, albedo, depth and ao)");
  cmd->add_flag("--no-preview", args->no_preview,
                "with .exr/.hdr output, do not also write a tone-mapped .png");
  add_load_options(cmd, &args->load);
  add_lighting_options(cmd, &args->lighting);
  cmd->callback([args] { run_render(*args); });
}

}  // namespace illum::cli
