// `illum bake SCENE --kind prt -o FOLDER` (the PRT half of cmd_bake.cpp) and
// `illum relight SCENE --prt FOLDER (--sun X,Y,Z | --env FILE) -o IMAGE`: bakes SH transfer
// (bake/prt_baker.h) into the folder of bake/prt_file.h and renders it under a distant light
// (bake/prt_relight.h).
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_file.h"
#include "illum/bake/prt_relight.h"
#include "illum/bake/prt_vq.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/core/tonemap.h"
#include "illum/render/render_setup.h"
#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// "X,Y,Z" as three finite numbers, or an Error naming the option.
vec3 parse_vector(const std::string& text, const char* option) {
  vec3 v(0.0f);
  const char* p = text.data();
  const char* end = text.data() + text.size();
  for (int i = 0; i < 3; ++i) {
    const auto r = std::from_chars(p, end, v[i], std::chars_format::general);
    if (r.ec != std::errc() || !std::isfinite(v[i]))
      throw Error(fmt::format("{} '{}': expected three finite numbers X,Y,Z", option, text));
    p = r.ptr;
    if (i < 2) {
      if (p == end || *p != ',')
        throw Error(fmt::format("{} '{}': expected three finite numbers X,Y,Z", option, text));
      ++p;
    }
  }
  if (p != end)
    throw Error(fmt::format("{} '{}': expected three finite numbers X,Y,Z", option, text));
  return v;
}

struct RelightArgs {
  std::string scene, prt, output, sun, env, lookup = "texels", tonemap = "clamp";
  float irradiance = kPi;
  float rotate = 0.0f;
  float exposure = 1.0f;
  int width = 0, height = 0, spp = 4, threads = 0;
  LoadOptions load;
};

void run_relight(const RelightArgs& args) {
  check_output_path(args.output);
  if (args.sun.empty() == args.env.empty())
    throw Error("relight: give exactly one light, --sun X,Y,Z or --env FILE");
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
  std::optional<vec3> sun;
  if (!args.sun.empty()) sun = parse_vector(args.sun, "--sun");  // zero: sun_light refuses it
  std::optional<Environment> env;
  if (!args.env.empty()) {
    env.emplace();
    env->path = args.env;
    env->radiance = read_image(args.env, false);
    env->rotation_y = radians(args.rotate);
  }
  bake::PrtSet set = bake::load_prt_set(args.prt);
  const bake::ShLight light = sun ? bake::sun_light(set.bands, *sun, Color(args.irradiance))
                                  : bake::environment_light(set.bands, *env);
  Scene scene = load_scene(args.scene, args.load);
  bake::apply_prt_set(scene, set);
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
    write_image(args.output, tone_mapped(image, mapper, args.exposure));
  std::fprintf(stderr, "illum: relight %s, %d bands %s (%s), %dx%d %d spp in %.2fs -> %s\n",
               scene.name.c_str(), set.bands, bake::to_string(set.mode), args.lookup.c_str(),
               options.width, options.height, options.samples, seconds, args.output.c_str());
}

}  // namespace

void run_prt_bake(const PrtBakeRequest& args) {
  bake::check_prt_output(args.output);
  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"resolution", "--resolution"},
                               {"texel_size", "--texel-size"},
                               {"spp", "--spp"},
                               {"bands", "--bands"},
                               {"mode", "--mode"},
                               {"seed", "--seed"},
                               {"reuse_uv1", "--regenerate-uv1"}});
  j["resolution"] = args.resolution;
  j["reuse_uv1"] = !args.regenerate_uv1;
  j["texel_size"] = args.texel_size;
  j["spp"] = args.spp;
  j["bands"] = args.bands;
  j["mode"] = args.mode;
  j["seed"] = args.seed;
  const Params params(j, "--param");
  const atlas::AtlasOptions atlas_options = atlas::AtlasOptions::from_params(params);
  bake::PrtBakeOptions options = bake::PrtBakeOptions::from_params(params);
  params.check_all_used();
  options.threads = args.threads;

  ThreadLimit limit(args.threads);
  Scene scene = load_scene(args.scene, args.load);
  bake::PrtSet set;
  set.scene_triangles = scene.triangle_count();
  auto t0 = std::chrono::steady_clock::now();
  set.atlas = atlas::chart_scene(scene, atlas_options);
  const double atlas_s = seconds_since(t0);
  const RayTracer tracer(scene);
  atlas::TexelRaster raster = atlas::rasterize_texels(scene, set.atlas.width, set.atlas.height);
  // As `illum bake` does: texel samples inside or behind geometry would leak light into the
  // transfer (bake/lightmap_seams.h).
  const bake::TexelPushOut pushed = bake::keep_texels_out_of_geometry(scene, tracer, raster);
  log::release();
  bake::PrtBake baked = bake::bake_prt(scene, tracer, raster, options);

  set.bands = baked.bands;
  set.mode = baked.mode;
  set.texel_transfer = std::move(baked.texel_transfer);
  set.vertex_transfer = std::move(baked.vertex_transfer);
  double vq_seconds = 0.0;
  if (args.vq > 0) {
    const auto tv = std::chrono::steady_clock::now();
    bake::VqOptions vq;
    vq.representatives = args.vq;
    vq.seed = args.seed;
    set.vq = bake::vq_compress(set.texel_transfer.data, set.texel_transfer.channels, vq);
    vq_seconds = seconds_since(tv);
  }
  set.scene = scene.name;
  set.scene_hash = geometry_hash_hex(scene);  // with the atlas applied, as apply_prt_set checks
  set.bake = {{"spp", options.spp},
              {"seed", options.seed},
              {"dilate", options.dilate},
              {"stitch", options.stitch},
              {"stitch_coplanar", options.stitch_coplanar},
              {"seam_edges", baked.seam_edges},
              {"coplanar_edges", baked.coplanar_edges},
              {"stitch_seconds", baked.stitch_seconds},
              {"shoot_tolerance", options.shoot_tolerance},
              {"shoot_relative_tolerance", options.shoot_relative_tolerance},
              {"max_rounds", options.max_rounds},
              {"normal_maps", options.normal_maps},
              {"normal_map_samples", options.normal_map_samples},
              {"texels", baked.texels},
              {"vertices", baked.vertices},
              {"rays", baked.rays},
              {"atlas_seconds", atlas_s},
              {"bake_seconds", baked.seconds},
              {"shoot_seconds", baked.shoot_seconds},
              {"texels_pushed_out", pushed.moved},
              {"texels_rejected", pushed.rejected}};
  set.bake.update(bake::shooting_record(baked));
  if (set.vq.count() > 0) {
    const double full = double(set.texel_transfer.data.size()) * 4.0;
    const double packed =
        double(set.vq.representatives.size()) * 4.0 + double(set.vq.indices.size()) * 2.0;
    set.bake["vq_seconds"] = vq_seconds;
    set.bake["vq_compression"] = full / packed;
    std::fprintf(stderr,
                 "illum: VQ %d representatives, %d iterations, max distance %.4g, rms %.4g, "
                 "%.1f:1 against the f32 map, %.2fs\n",
                 set.vq.count(), set.vq.iterations, set.vq.max_distance, set.vq.rms_distance,
                 full / packed, vq_seconds);
  }
  bake::save_prt_set(args.output, set);
  std::fprintf(stderr,
               "illum: bake %s, prt %d bands %s: atlas %dx%d, %zu texels, %zu vertices, %d spp "
               "in %.2fs (shooting %.2fs, %d rounds, unshot %.2g) -> %s\n",
               scene.name.c_str(), set.bands, bake::to_string(set.mode), set.atlas.width,
               set.atlas.height, baked.texels, baked.vertices, options.spp, baked.seconds,
               baked.shoot_seconds, baked.shoot_rounds, baked.unshot_fraction, args.output.c_str());
}

void add_relight_command(CLI::App& app) {
  auto args = std::make_shared<RelightArgs>();
  auto* cmd = app.add_subcommand(
      "relight", "Render baked PRT transfer (illum bake --kind prt) under a sun or an environment");
  cmd->add_option("scene", args->scene, "the scene the folder was baked for")->required();
  cmd->add_option("--prt", args->prt, "PRT folder written by `illum bake --kind prt`")->required();
  cmd->add_option("-o,--output", args->output, "output image (.png, .exr, .hdr, ...)")->required();
  cmd->add_option("--sun", args->sun, "sun: direction the light travels X,Y,Z (as in scene files)");
  cmd->add_option("--irradiance", args->irradiance,
                  "sun irradiance E (W/m²) on a surface facing it (default π: a white surface "
                  "facing it shows radiance 1)")
      ->transform(number(0.0f, FLT_MAX));
  cmd->add_option("--env", args->env, "environment: equirectangular HDR image");
  cmd->add_option("--rotate", args->rotate, "turn the environment about +y by DEG degrees")
      ->transform(number(-36000.0f, 36000.0f));
  cmd->add_option(
         "--lookup", args->lookup,
         "texels (SHL-map, bilinear), vertices, or vq (the compressed map, 4 taps at ±¼ texel)")
      ->capture_default_str();
  cmd->add_option("--width", args->width, "image width (default: the scene's)")
      ->transform(number(1, 16384));
  cmd->add_option("--height", args->height, "image height (default: the scene's)")
      ->transform(number(1, 16384));
  cmd->add_option("--spp", args->spp, "primary rays per pixel")
      ->transform(number(1, 4096))
      ->capture_default_str();
  cmd->add_option("--exposure", args->exposure, "exposure multiplier for 8-bit output")
      ->transform(number(FLT_MIN, FLT_MAX));
  cmd->add_option("--tonemap", args->tonemap, "clamp, reinhard or aces (8-bit output)");
  cmd->add_option("--threads", args->threads, "worker threads (0: all cores)")
      ->transform(number(0, 4096));
  add_load_options(cmd, &args->load);
  cmd->callback([args] { run_relight(*args); });
}

}  // namespace illum::cli
