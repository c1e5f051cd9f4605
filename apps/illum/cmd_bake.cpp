// `illum bake SCENE -o FOLDER`: builds the scene's light-map atlas, bakes a path-traced
// (`--method path`) or radiosity (`--method radiosity`) light-map in the chosen basis and
// writes the folder `illum frame --baked` and
// `illum view --baked` read (format: baked/lightmap_file.h).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/atlas_report.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/bake_memory.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/lightmap_extras.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/bake/probe_baker.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_vq.h"
#include "illum/bake/radiosity_baker.h"
#include "illum/baked/lightmap_file.h"
#include "illum/baked/probe_file.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"
#include "job_role.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

struct BakeArgs {
  std::string scene;
  std::string output;
  std::string method = "path";
  double threshold = bake::kDefaultRadiosityThreshold;
  double time_s = 0.0;
  bool spp_given = false, bounces_given = false, threshold_given = false, time_given = false;
  std::string basis = "plain";
  std::string content = "all";
  int resolution = 512;
  float texel_size = 0.0f;
  bool regenerate_uv1 = false;
  int spp = 256;
  int max_bounces = 8;
  uint64_t seed = 0;
  int threads = 0;
  std::string extras;  // comma-separated extra maps (bake/lightmap_extras.h)
  float ao_distance = 0.0f;
  float obscurance_dmax = bake::kDefaultObscuranceDmax;
  int extras_rays = bake::kDefaultExtraRays;
  std::vector<std::string> params;  // atlas and baker keys
  LoadOptions load;
  LightingArgs lighting;          // --sun, --sky
  std::string kind = "lightmap";  // lightmap | prt (cmd_bake_prt.cpp) | probes (run_probe_bake)
  float spacing = 0.0f;           // probes only; 0: not given (the grid's default)
  int bands = 4;                  // prt only
  int vq = 0;                     // prt only
  std::string mode = "shadowed";  // prt only
};

// One line when meshes kept their own UV1: how many, and the texel density they got (their
// layout's own, scaled to the nominal density on average: atlas/atlas_report.h).
void report_reused_uv1(const Scene& scene, const atlas::Atlas& atlas) {
  const atlas::AtlasStats stats = atlas::measure_atlas(scene, atlas);
  int reused = 0;
  double lo = 0.0, hi = 0.0;
  for (size_t m = 0; m < atlas.meshes.size(); ++m) {
    if (!atlas.meshes[m].reused_uv1 || stats.meshes[m].triangles == 0) continue;
    lo = reused ? std::min(lo, stats.meshes[m].min_density) : stats.meshes[m].min_density;
    hi = reused ? std::max(hi, stats.meshes[m].max_density) : stats.meshes[m].max_density;
    ++reused;
  }
  if (reused > 0)
    std::fprintf(stderr,
                 "illum: bake: kept the UV1 of %d mesh%s (texel density %.3g to %.3g of the "
                 "nominal; --regenerate-uv1 charts them anew)\n",
                 reused, reused == 1 ? "" : "es", lo, hi);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// `--kind probes`: an irradiance-probe grid (bake/probe_baker.h) into the folder of
// baked/probe_file.h. Instances marked dynamic are left out of the traced and hashed geometry.
void run_probe_bake(const BakeArgs& args, const CLI::App& cmd) {
  for (const char* option :
       {"--basis", "--content", "--extras", "--ao-distance", "--obscurance-dmax", "--extras-rays",
        "--method", "--threshold", "--time", "--resolution", "--texel-size"})
    if (cmd.count(option)) throw Error(fmt::format("{} does not apply to --kind probes", option));
  if (cmd.count("--spacing") && !(args.spacing > 0.0f))
    throw Error(fmt::format("--spacing {}: must be > 0 metres", args.spacing));
  baked::check_probe_output(args.output);  // before the long work, not after
  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"spacing", "--spacing"},
                               {"spp", "--spp"},
                               {"seed", "--seed"},
                               {"max_bounces", "--bounces"}});
  j["spacing"] = args.spacing;
  j["spp"] = args.spp;
  j["seed"] = args.seed;
  if (args.bounces_given) j["max_bounces"] = args.max_bounces;
  const Params params(j, "--param");
  params.unlist({"spacing", "spp", "seed", "max_bounces"});
  bake::ProbeBakeOptions options = bake::ProbeBakeOptions::from_params(params);
  params.check_all_used();
  const int threads = threads_for_this_rank(args.threads);
  options.threads = threads;

  ThreadLimit limit(threads);
  Scene loaded = load_scene(args.scene, args.load);
  apply_lighting_options(loaded, args.lighting, "probe bake", Unlit::kRefuse);
  const Scene scene = bake::static_part(loaded);
  const RayTracer tracer(scene);
  try {  // the grid's size first: a refused grid names the option
    bake::make_probe_grid(tracer.bounds(), options.spacing);
  } catch (const Error& e) {
    throw Error(fmt::format("--spacing {}: {}", args.spacing, e.what()));
  }
  log::release();
  const bake::ProbeBake baked = bake::bake_probes(scene, tracer, options);
  if (!writes_output()) return;  // rank 0 of the MPI job holds the probes
  stop_if_interrupted();
  baked::ProbeSet set;
  set.grid = baked.grid;
  set.probes = baked.probes;
  set.backface_threshold = options.backface_threshold;
  set.scene = loaded.name;
  set.scene_triangles = scene.triangle_count();
  set.scene_hash = geometry_hash_hex(scene);  // the static part, as check_probe_scene
  set.bake = {{"spp", options.spp},
              {"max_bounces", options.max_bounces},
              {"seed", options.seed},
              {"rays", baked.stats.rays},
              {"invalid", baked.stats.invalid},
              {"bake_seconds", baked.stats.seconds}};
  baked::save_probe_set(args.output, set);
  const glm::ivec3 n = set.grid.size;
  std::fprintf(
      stderr,
      "illum: bake %s, probes: %dx%dx%d grid, spacing %.4g m, %lld probes (%lld "
      "invalid), %d spp in %.2fs (%.2f Mrays/s) -> %s\n",
      loaded.name.c_str(), n.x, n.y, n.z, double(set.grid.spacing),
      static_cast<long long>(set.grid.count()), static_cast<long long>(baked.stats.invalid),
      options.spp, baked.stats.seconds,
      baked.stats.seconds > 0 ? double(baked.stats.rays) / baked.stats.seconds * 1e-6 : 0.0,
      args.output.c_str());
}

// Options of another kind are refused rather than ignored.
void check_kind_options(const BakeArgs& args, const CLI::App& cmd) {
  if (args.kind != "lightmap" && args.kind != "prt" && args.kind != "probes")
    throw Error(fmt::format("--kind '{}': lightmap, prt or probes", args.kind));
  for (const char* option : {"--bands", "--mode", "--vq"})
    if (args.kind != "prt" && cmd.count(option))
      throw Error(fmt::format("{} applies to --kind prt only", option));
  if (args.kind != "probes" && cmd.count("--spacing"))
    throw Error("--spacing applies to --kind probes only");
}

// `--kind prt`: SH transfer (run_prt_bake, cmd_bake_prt.cpp).
void run_prt_kind_bake(const BakeArgs& args, const CLI::App& cmd) {
  for (const char* option :
       {"--basis", "--content", "--extras", "--ao-distance", "--obscurance-dmax", "--extras-rays",
        "--method", "--threshold", "--time"})
    if (cmd.count(option)) throw Error(fmt::format("{} applies to --kind lightmap only", option));
  if (cmd.count("--bounces"))
    throw Error("--bounces applies to --kind lightmap and probes (prt: --mode interreflected)");
  for (const char* option : {"--sun", "--sky"})
    if (cmd.count(option))
      throw Error(fmt::format("{}: PRT transfer holds no light; give the light to `illum relight`",
                              option));
  // The interreflected transfer is one shooting loop over every patch; the other modes
  // are not split yet either.
  refuse_with_several_ranks(true, "bake --kind prt", "its work is not split across ranks");
  PrtBakeRequest request{args.scene,         args.output, args.mode,    args.resolution,
                         args.spp,           args.bands,  args.threads, args.vq,
                         args.texel_size,    args.seed,   args.params,  args.load,
                         args.regenerate_uv1};
  run_prt_bake(request);
}

// What a light-map bake's options and --param keys come to, checked before any long work.
struct LightmapPlan {
  bool radiosity = false;    // --method radiosity, else path
  bool extras_only = false;  // --basis none: the extra maps without light-map layers
  int threads = 0;
  atlas::AtlasOptions atlas;
  bake::LightmapBakeOptions path;
  bake::RadiosityBakeOptions radiosity_options;
  bake::LightmapExtrasOptions extras;
};

// --method and the options that apply to one method only (refused for the other).
void check_method_options(const BakeArgs& args, bool radiosity) {
  if (!radiosity && args.method != "path")
    throw Error(fmt::format("--method must be path or radiosity, not '{}'", args.method));
  if (radiosity && (args.spp_given || args.bounces_given))
    throw Error(fmt::format("{} applies to --method path, not radiosity",
                            args.spp_given ? "--spp" : "--bounces"));
  if (!radiosity && args.threshold_given)
    throw Error("--threshold applies to --method radiosity, not path");
  if (args.time_given && !(args.time_s >= 0.0 && std::isfinite(args.time_s)))
    throw Error(fmt::format("--time {}: must be a number of seconds >= 0", args.time_s));
  // The path baker stops between passes that double every texel's samples (bake/
  // lightmap_baker.h), so the samples it may end at are the powers of two up to --spp.
  if (!radiosity && args.time_s > 0.0 && (args.spp & (args.spp - 1)) != 0)
    throw Error(
        fmt::format("--spp {} with --time: must be a power of two (the path bake stops "
                    "between passes of 1, 2, 4, ... samples per texel)",
                    args.spp));
  refuse_with_several_ranks(radiosity, "bake --method radiosity",
                            "progressive shooting is one sequential loop over every patch");
  refuse_with_several_ranks(args.time_s > 0.0, fmt::format("--time {}", args.time_s),
                            "the samples taken in the time would depend on the ranks; give "
                            "--spp instead");
}

// `--basis none` bakes the extra maps alone (AO in seconds where the light-map takes
// minutes): it needs --extras, and the options of the light-map layers are refused rather
// than ignored.
void check_extras_only_options(const BakeArgs& args, const CLI::App& cmd) {
  if (args.extras.empty())
    throw Error(
        "--basis none bakes only the extra maps: name them with --extras (ao, obscurance, "
        "bent_normal)");
  for (const char* option :
       {"--content", "--method", "--spp", "--bounces", "--threshold", "--time", "--sun", "--sky"})
    if (cmd.count(option))
      throw Error(fmt::format(
          "{} does not apply to --basis none (no light-map layers are baked; the extra maps "
          "need no light)",
          option));
}

// The atlas and baker options from the dedicated options and the --param keys (a key that
// a dedicated option sets is refused).
void read_lightmap_params(const BakeArgs& args, LightmapPlan* plan) {
  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"resolution", "--resolution"},
                               {"texel_size", "--texel-size"},
                               {"basis", "--basis"},
                               {"content", "--content"},
                               {"spp", "--spp"},
                               {"max_bounces", "--bounces"},
                               {"seed", "--seed"},
                               {"threshold", "--threshold"},
                               {"reuse_uv1", "--regenerate-uv1"}});
  j["resolution"] = args.resolution;
  j["reuse_uv1"] = !args.regenerate_uv1;
  j["texel_size"] = args.texel_size;
  // --basis none bakes no layers; the baker's options are still read (dilate) in one place.
  j["basis"] = plan->extras_only ? "plain" : args.basis;
  j["content"] = args.content;
  j["seed"] = args.seed;
  if (plan->radiosity) {
    j["threshold"] = args.threshold;
  } else {
    j["spp"] = args.spp;
    j["max_bounces"] = args.max_bounces;
  }
  const Params params(j, "--param");
  params.unlist({"resolution", "texel_size", "basis", "content", "spp", "max_bounces", "seed",
                 "threshold", "reuse_uv1"});
  plan->atlas = atlas::AtlasOptions::from_params(params);
  if (plan->radiosity) {
    plan->radiosity_options = bake::RadiosityBakeOptions::from_params(params);
    plan->radiosity_options.threads = plan->threads;
    plan->radiosity_options.time_budget_s = args.time_s;
    plan->extras.dilate = plan->radiosity_options.dilate;
  } else {
    plan->path = bake::LightmapBakeOptions::from_params(params);
    plan->path.threads = plan->threads;
    plan->path.time_budget_s = args.time_s;
    plan->extras.dilate = plan->path.dilate;
  }
  params.check_all_used();
}

LightmapPlan plan_lightmap_bake(const BakeArgs& args) {
  LightmapPlan plan;
  if (!args.extras.empty()) plan.extras.select(args.extras);
  plan.extras.ao_distance = args.ao_distance;
  plan.extras.obscurance_dmax = args.obscurance_dmax;
  plan.extras.rays = args.extras_rays;
  plan.extras.seed = args.seed;
  plan.threads = threads_for_this_rank(args.threads);
  plan.extras.threads = plan.threads;
  baked::check_lightmap_output(args.output);  // before the long work, not after
  plan.radiosity = args.method == "radiosity";
  plan.extras_only = args.basis == "none";
  check_method_options(args, plan.radiosity);
  read_lightmap_params(args, &plan);
  return plan;
}

// Before the raster and the bake allocate per texel: a bake the machine cannot hold is
// refused with the estimate rather than killed an hour later (bake/bake_memory.h).
void check_lightmap_memory(const atlas::Atlas& atlas, const LightmapPlan& plan, double time_s,
                           size_t scene_triangles) {
  const bool radiosity = plan.radiosity;
  bake::BakeMemoryInput memory;
  memory.atlas_texels = int64_t(atlas.width) * atlas.height;
  memory.chart_texels = bake::chart_texel_bound(atlas);
  memory.layers = plan.extras_only ? 0
                                   : bake::layer_count(radiosity ? plan.radiosity_options.basis
                                                                 : plan.path.basis);
  memory.extra_maps = (plan.extras.ao ? 1 : 0) + (plan.extras.obscurance ? 2 : 0) +
                      (plan.extras.bent_normal ? 1 : 0);
  memory.radiosity = radiosity;
  memory.denoise = !radiosity && !plan.extras_only && plan.path.denoise;
  memory.timed = !radiosity && time_s > 0.0;
  memory.scene_triangles = static_cast<int64_t>(scene_triangles);
  bake::check_bake_memory(bake::estimate_bake_memory(memory), bake::machine_memory());
}

// The layers by the chosen method; a radiosity bake's own figures go to *radiosity_baked.
bake::LightmapBake bake_layers(const Scene& scene, const RayTracer& tracer,
                               const atlas::TexelRaster& raster, const LightmapPlan& plan,
                               bake::RadiosityBake* radiosity_baked) {
  if (!plan.radiosity) return bake::bake_lightmap(scene, tracer, raster, plan.path);
  *radiosity_baked = bake::bake_radiosity(scene, tracer, raster, plan.radiosity_options);
  bake::LightmapBake baked;
  baked.basis = radiosity_baked->basis;
  baked.content = radiosity_baked->content;
  baked.layers = std::move(radiosity_baked->layers);
  baked.seconds = radiosity_baked->seconds;
  baked.stitch_seconds = radiosity_baked->stitch_seconds;
  baked.seam_edges = radiosity_baked->seam_edges;
  baked.coplanar_edges = radiosity_baked->coplanar_edges;
  baked.rays = radiosity_baked->rays;
  baked.texels = radiosity_baked->texels;
  return baked;
}

// The extra maps (--extras) beside the layers, each with its manifest entry.
bake::LightmapExtras bake_extras(const Scene& scene, const RayTracer& tracer,
                                 const atlas::TexelRaster& raster,
                                 const bake::LightmapExtrasOptions& options,
                                 baked::LightmapSet* set) {
  bake::LightmapExtras extras = bake::bake_lightmap_extras(scene, tracer, raster, options);
  const nlohmann::json common = {{"rays", options.rays}, {"seed", options.seed}};
  auto add = [&](const char* name, Image& image, nlohmann::json entry) {
    entry.update(common);
    set->extras.push_back({name, std::move(image), std::move(entry)});
  };
  if (options.ao) add("ao", extras.ao, {{"distance", extras.ao_distance}});
  if (options.obscurance) {
    add("obscurance", extras.obscurance, {{"d_max", options.obscurance_dmax}});
    const Color& r = extras.average_albedo;
    add("obscurance_color", extras.obscurance_color,
        {{"d_max", options.obscurance_dmax}, {"average_albedo", {r.x, r.y, r.z}}});
  }
  if (options.bent_normal)
    add("bent_normal", extras.bent_normal,
        {{"distance", extras.ao_distance}, {"encoding", "world-space unit xyz in [-1, 1]"}});
  return extras;
}

// The manifest's "bake" object: the method's options and figures.
nlohmann::json method_manifest(const LightmapPlan& plan, double time_s,
                               const bake::LightmapBake& baked,
                               const bake::RadiosityBake& radiosity_baked) {
  if (plan.radiosity) {
    const bake::RadiosityBakeOptions& o = plan.radiosity_options;
    return {{"method", "radiosity"},
            {"threshold", o.threshold},
            {"relative_threshold", o.relative_threshold},
            {"group_size", o.group_size},
            {"samples_per_surface", o.samples_per_surface},
            {"sky_rays", o.sky_rays},
            {"reach_rays", o.reach_rays},
            {"cluster_ratio", o.cluster_ratio},
            {"seed", o.seed},
            {"dilate", o.dilate},
            {"stitch", o.stitch},
            {"stitch_coplanar", o.stitch_coplanar},
            {"shots", radiosity_baked.shots},
            {"visibility_rays", radiosity_baked.visibility_rays},
            {"initial_power", radiosity_baked.initial_power},
            {"relative_unshot", radiosity_baked.relative_unshot},
            {"relative_shots", radiosity_baked.relative_shots},
            {"remaining_power", radiosity_baked.remaining_power},
            {"converged", radiosity_baked.converged}};
  }
  const bake::LightmapBakeOptions& o = plan.path;
  nlohmann::json j = {{"method", "path"},
                      {"spp", baked.spp},  // samples taken per texel
                      {"max_bounces", o.max_bounces},
                      {"seed", o.seed},
                      {"dilate", o.dilate},
                      {"stitch", o.stitch},
                      {"stitch_coplanar", o.stitch_coplanar},
                      {"denoise", baked.denoised},
                      {"denoise_strength", o.denoise_strength}};
  if (time_s > 0.0)
    j.update(nlohmann::json{{"spp_requested", o.spp},
                            {"time_budget", time_s},
                            {"passes", baked.passes},
                            {"stopped_by_time", baked.stopped_by_time}});
  return j;
}

// The one line a finished bake prints.
void report_lightmap_bake(const Scene& scene, const baked::LightmapSet& set,
                          const LightmapPlan& plan, const bake::LightmapBake& baked,
                          const bake::RadiosityBake& radiosity_baked, size_t covered,
                          double occupancy, double atlas_s, double raster_s,
                          const std::string& output) {
  const std::string denoised =
      baked.denoised ? fmt::format(", denoised in {:.2f}s", baked.denoise_seconds) : "";
  const std::string method =
      plan.radiosity
          ? fmt::format("radiosity {} shots, {:.2g} of the power left unshot{}",
                        radiosity_baked.shots,
                        radiosity_baked.initial_power > 0
                            ? radiosity_baked.remaining_power / radiosity_baked.initial_power
                            : 0.0,
                        radiosity_baked.converged ? "" : " (stopped by --time)")
          : fmt::format("{} spp{}", baked.spp,
                        baked.stopped_by_time
                            ? fmt::format(" of {} (stopped by --time)", plan.path.spp)
                            : "");
  std::fprintf(stderr,
               "illum: bake %s, %s/%s: atlas %dx%d, %d charts, texel %.4g m, %zu texels "
               "(%.1f%% of the atlas) in %.2fs; raster %.2fs; bake %s %.2fs (%.2f Mrays/s)%s "
               "-> %s\n",
               scene.name.c_str(), set.basis.c_str(), set.content.c_str(), set.atlas.width,
               set.atlas.height, set.atlas.chart_count, double(set.atlas.texel_size), covered,
               100.0 * occupancy, atlas_s, raster_s, method.c_str(), baked.seconds,
               baked.seconds > 0 ? double(baked.rays) / baked.seconds * 1e-6 : 0.0,
               denoised.c_str(), output.c_str());
}

// `--kind lightmap`: chart the atlas, rasterize its texels, bake the layers (path or
// radiosity) and the extra maps, and write the folder of baked/lightmap_file.h.
void run_lightmap_bake(const BakeArgs& args) {
  const LightmapPlan plan = plan_lightmap_bake(args);

  ThreadLimit limit(plan.threads);
  Scene scene = load_scene(args.scene, args.load);
  if (!plan.extras_only)  // the extra maps are geometry alone: an unlit scene is no concern
    apply_lighting_options(scene, args.lighting,
                           args.method == "radiosity" ? "radiosity bake" : "bake",
                           args.method == "radiosity" ? Unlit::kRefuse : Unlit::kWarn);
  const size_t scene_triangles = scene.triangle_count();

  auto t0 = std::chrono::steady_clock::now();
  baked::LightmapSet set;
  set.atlas = atlas::chart_scene(scene, plan.atlas);
  report_reused_uv1(scene, set.atlas);
  check_lightmap_memory(set.atlas, plan, args.time_s, scene_triangles);
  const double atlas_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const RayTracer tracer(scene);
  atlas::TexelRaster raster = atlas::rasterize_texels(scene, set.atlas.width, set.atlas.height);
  // Samples inside or behind geometry would leak light (bake/lightmap_seams.h).
  const bake::TexelPushOut pushed = bake::keep_texels_out_of_geometry(scene, tracer, raster);
  const double raster_s = seconds_since(t0);
  // The loader drops zero-area triangles and the raster skips any left: a scene of nothing
  // else would give an empty folder that every reader shows as black.
  if (raster.covered() == 0)
    throw Error(fmt::format(
        "{}: nothing to bake: no triangle with area covers a texel of the "
        "{}x{} atlas ({} triangles, {} charts)",
        args.scene, set.atlas.width, set.atlas.height, scene_triangles, set.atlas.chart_count));

  log::release();  // the input is checked: the load's warnings may show now
  bake::RadiosityBake radiosity_baked;
  bake::LightmapBake baked;
  if (!plan.extras_only) baked = bake_layers(scene, tracer, raster, plan, &radiosity_baked);
  bake::LightmapExtras extras;
  if (plan.extras.any()) extras = bake_extras(scene, tracer, raster, plan.extras, &set);

  if (!writes_output()) return;  // rank 0 of the MPI job holds the maps
  stop_if_interrupted();
  set.basis = plan.extras_only ? "none" : bake::to_string(baked.basis);
  set.content = plan.extras_only ? "none" : bake::to_string(baked.content);
  set.layers = std::move(baked.layers);
  set.scene = scene.name;
  set.scene_triangles = scene_triangles;
  set.scene_hash = geometry_hash_hex(scene);  // with the atlas applied, as the readers check it
  const double occupancy =
      double(raster.covered()) / (double(set.atlas.width) * double(set.atlas.height));
  set.bake = plan.extras_only ? nlohmann::json{{"method", "none"}, {"dilate", plan.extras.dilate}}
                              : method_manifest(plan, args.time_s, baked, radiosity_baked);
  set.bake.update(nlohmann::json{{"texels", plan.extras_only ? raster.covered() : baked.texels},
                                 {"occupancy", occupancy},
                                 {"rays", baked.rays},
                                 {"atlas_seconds", atlas_s},
                                 {"raster_seconds", raster_s},
                                 {"texels_pushed_out", pushed.moved},
                                 {"texels_rejected", pushed.rejected},
                                 {"bake_seconds", baked.seconds},
                                 {"denoise_seconds", baked.denoise_seconds},
                                 {"seam_edges", baked.seam_edges},
                                 {"coplanar_edges", baked.coplanar_edges},
                                 {"stitch_seconds", baked.stitch_seconds}});
  if (plan.extras.any()) {
    set.bake["extras_seconds"] = extras.seconds;
    set.bake["extras_rays"] = extras.rays;
  }
  baked::save_lightmap_set(args.output, set);
  if (plan.extras_only)
    std::fprintf(stderr,
                 "illum: bake %s, extra maps only (%s): atlas %dx%d, %d charts, %zu texels in "
                 "%.2fs; raster %.2fs; %d rays per texel %.2fs -> %s\n",
                 scene.name.c_str(), args.extras.c_str(), set.atlas.width, set.atlas.height,
                 set.atlas.chart_count, raster.covered(), atlas_s, raster_s, plan.extras.rays,
                 extras.seconds, args.output.c_str());
  else
    report_lightmap_bake(scene, set, plan, baked, radiosity_baked, raster.covered(), occupancy,
                         atlas_s, raster_s, args.output);
}

// `illum bake`: one handler per --kind.
void run_bake(const BakeArgs& args, const CLI::App& cmd) {
  check_kind_options(args, cmd);
  if (args.kind == "probes")
    run_probe_bake(args, cmd);
  else if (args.kind == "prt")
    run_prt_kind_bake(args, cmd);
  else {
    if (args.basis == "none") check_extras_only_options(args, cmd);
    run_lightmap_bake(args);
  }
}

}  // namespace

void add_bake_command(CLI::App& app) {
  auto args = std::make_shared<BakeArgs>();
  auto* cmd = app.add_subcommand(
      "bake",
      "Bake a path-traced or radiosity light-map (atlas, plain/RNM/SH-L1 layers) into a folder");
  cmd->add_option("scene", args->scene,
                  "scene file (.obj, .gltf, .glb, .illum.json) or built-in name")
      ->required();
  cmd->add_option("-o,--output", args->output,
                  "output folder (created; an earlier light-map folder is replaced)")
      ->required();
  cmd->add_option("--method", args->method,
                  "path (path-traced, denoised) or radiosity (progressive-refinement shooting, "
                  "one patch per texel)")
      ->check(CLI::IsMember({"path", "radiosity"}))
      ->capture_default_str();
  cmd->add_option("--threshold", args->threshold,
                  "radiosity: stop when the unshot power is at most this share of the initial "
                  "(direct light and emission)")
      ->transform(number(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--time", args->time_s,
                  "stop after about this many seconds (0: no limit). radiosity: stops shooting; "
                  "the map then holds what was shot. path: bakes passes of 1, 2, 4, ... "
                  "samples per texel up to --spp (a power of two) and skips a pass predicted "
                  "to end past the time; the manifest records the samples taken")
      ->transform(number(0.0, 1e9))
      ->capture_default_str();
  cmd->add_option("--basis", args->basis,
                  "plain, rnm (3 Source basis maps), sh (SH-L1), dominant (ambient, "
                  "directional colour, dominant direction) or none (only the --extras maps)")
      ->check(CLI::IsMember({"plain", "rnm", "sh", "dominant", "none"}))
      ->capture_default_str();
  cmd->add_option("--content", args->content,
                  "all (every light, direct and indirect) or indirect (leaves the direct light "
                  "of point, spot and sun lights to the real-time renderer)")
      ->check(CLI::IsMember({"all", "indirect"}))
      ->capture_default_str();
  // Well-formed numbers of the right sign here; the atlas and the baker own the exact ranges.
  cmd->add_option("--resolution", args->resolution, "atlas side in texels")
      ->transform(number(atlas::kMinResolution, atlas::kMaxResolution))
      ->capture_default_str();
  cmd->add_option("--texel-size", args->texel_size,
                  "metres per texel (0: the finest that fits the resolution)")
      ->transform(number(0.0f, FLT_MAX))
      ->capture_default_str();
  cmd->add_flag("--regenerate-uv1", args->regenerate_uv1,
                "chart every mesh anew; without it a mesh's own light-map UVs (glTF "
                "TEXCOORD_1) are kept when valid (an invalid set is a warning and charted anew)");
  cmd->add_option("--spp", args->spp,
                  "hemisphere samples per texel (probes: sphere samples per probe)")
      ->transform(number(1, INT_MAX))
      ->capture_default_str();
  cmd->add_option("--bounces", args->max_bounces,
                  "longest path in bounces after the texel (probes: after the probe)")
      ->transform(number(0, INT_MAX))
      ->capture_default_str();
  cmd->add_option("--seed", args->seed,
                  "random seed (same seed: same maps, whatever the thread count)")
      ->transform(number<uint64_t>(0, UINT64_MAX));
  cmd->add_option("--threads", args->threads,
                  "worker threads (0: all cores; under mpirun the node's cores over its ranks)")
      ->transform(number(0, 4096));
  cmd->add_option("--extras", args->extras,
                  "extra maps beside the layers, comma-separated: ao (cosine-weighted ambient "
                  "occlusion), obscurance (S000 §2.10, plain and with colour bleeding), "
                  "bent_normal");
  cmd->add_option("--ao-distance", args->ao_distance,
                  "occluder search distance of ao and bent_normal in scene units (0: 0.1 × the "
                  "scene's diagonal, as `illum render -i ao`)")
      ->transform(number(0.0f, FLT_MAX))
      ->capture_default_str();
  cmd->add_option("--obscurance-dmax", args->obscurance_dmax,
                  "obscurance distance d_max in scene units (surfaces farther count as open)")
      ->transform(number(FLT_MIN, FLT_MAX))
      ->capture_default_str();
  cmd->add_option("--extras-rays", args->extras_rays, "directions per texel for the extra maps")
      ->transform(number(1, bake::kMaxExtraRays))
      ->capture_default_str();
  cmd->add_option("-p,--param", args->params,
                  "atlas or baker parameter key=value (padding, max_chart_angle, dilate, "
                  "denoise=true|false, denoise_strength, stitch=true|false, "
                  "stitch_coplanar=true|false)");
  cmd->add_option("--kind", args->kind,
                  "lightmap (path-traced light-map), prt (SH transfer, docs/prt.md) or probes "
                  "(irradiance probe grid, docs/probes.md)")
      ->check(CLI::IsMember({"lightmap", "prt", "probes"}))
      ->capture_default_str();
  cmd->add_option("--spacing", args->spacing,
                  "probes: metres between probes (default: the scene's longest side / 16)")
      ->transform(number(0.0f, FLT_MAX));
  cmd->add_option("--bands", args->bands, "prt: SH bands (bands² coefficients)")
      ->transform(number(bake::kMinPrtBands, bake::kMaxPrtBands))
      ->capture_default_str();
  cmd->add_option("--vq", args->vq,
                  "prt: also store the SHL-map VQ-compressed into this many representatives "
                  "(16-bit indices; 0: not compressed)")
      ->transform(number(0, bake::kMaxVqRepresentatives))
      ->capture_default_str();
  cmd->add_option("--mode", args->mode, "prt: unshadowed, shadowed or interreflected")
      ->check(CLI::IsMember({"unshadowed", "shadowed", "interreflected"}))
      ->capture_default_str();
  add_load_options(cmd, &args->load);
  add_lighting_options(cmd, &args->lighting);
  cmd->callback([args, cmd] {
    args->spp_given = cmd->count("--spp") > 0;
    args->bounces_given = cmd->count("--bounces") > 0;
    args->threshold_given = cmd->count("--threshold") > 0;
    args->time_given = cmd->count("--time") > 0;
    run_bake(*args, *cmd);
  });
}

}  // namespace illum::cli
