// `illum-bench lightmap`: the path-traced light-map baker (bake/lightmap_baker.h) on built-in
// scenes (default: cornell; sibenik when asked), measured two ways in one run:
//  1. throughput against the camera path tracer, which shares its transport
//     (render/path_radiance.h): a plain, all-light bake of the scene's atlas and a path-traced
//     image of about as many pixels as the atlas has covered texels, at the same spp and path
//     length, interleaved for R rounds; medians and baker/path ratios of rays/s and samples/s;
//  2. the denoiser (bake/lightmap_denoiser.h): one low-spp raw bake is denoised exactly as
//     bake_lightmap does it, and both maps are compared with an independent high-spp bake:
//     relative RMSE of layer 0's luminance over covered texels, the mean ratio (bias), the
//     denoiser's seconds, and the reference's own noise from the baker's variance estimate.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/lightmap_denoiser.h"
#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/render/path_integrator.h"
#include "illum/render/render_setup.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct LightmapArgs {
  std::vector<std::string> scenes{"cornell"};
  int resolution = 0;     // 0: per scene (atlas_resolution)
  int spp = 16;           // throughput and the denoised bake
  int reference_spp = 0;  // 0: per scene (reference_spp)
  int max_bounces = 8;
  int repeats = 5;
  int threads = 0;
  uint64_t seed = 1;
  std::string json_path;
};

// Defaults that keep a run to a couple of minutes on 2 cores: Cornell's 32 triangles are
// cheap to trace, Sibenik's 75k and its 4× more texels per 512² are not.
bool is_cornell(const std::string& scene) {
  return scene == "cornell";
}
int atlas_resolution(const LightmapArgs& a, const std::string& scene) {
  return a.resolution > 0 ? a.resolution : is_cornell(scene) ? 256 : 512;
}
int reference_spp(const LightmapArgs& a, const std::string& scene) {
  return a.reference_spp > 0 ? a.reference_spp : is_cornell(scene) ? 1024 : 128;
}

bake::LightmapBakeOptions bake_options(const LightmapArgs& a, int spp, uint64_t seed) {
  bake::LightmapBakeOptions o;  // plain, all light, denoise off
  o.spp = spp;
  o.max_bounces = a.max_bounces;
  o.dilate = 0;  // dilation traces nothing: keep it out of the timed bake
  o.seed = seed;
  o.threads = a.threads;
  o.progress = false;
  return o;
}

// Per-round throughput of one method.
struct Throughput {
  std::vector<double> seconds, samples_per_s, rays_per_s;
  int64_t samples = 0, rays = 0;

  void add(double s, int64_t smp, int64_t r) {
    seconds.push_back(s);
    samples_per_s.push_back(static_cast<double>(smp) / s);
    rays_per_s.push_back(static_cast<double>(r) / s);
    samples = smp;
    rays = r;
  }
  double rays_per_sample() const {
    return static_cast<double>(rays) / static_cast<double>(samples);
  }
  nlohmann::json to_json() const {
    return {{"seconds", median(seconds)},
            {"seconds_runs", seconds},
            {"samples", samples},
            {"rays", rays},
            {"samples_per_s", median(samples_per_s)},
            {"rays_per_s", median(rays_per_s)},
            {"rays_per_s_runs", rays_per_s},
            {"rays_per_sample", rays_per_sample()}};
  }
};

// Median of the per-round ratios a[i]/b[i]: slow drifts of a shared machine cancel.
double paired_ratio(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> r;
  for (size_t i = 0; i < a.size(); ++i) r.push_back(a[i] / b[i]);
  return median(r);
}

// Layer 0 of `estimate` against `reference` over the covered texels, in luminance.
struct MapError {
  double relative_rmse = 0.0;  // √(mean (L − L_ref)²) / mean L_ref
  double mean = 0.0;           // mean L of the estimate
};

MapError compare(const atlas::TexelRaster& raster, const Image& estimate, const Image& reference) {
  double e2 = 0.0, sum = 0.0, sum_ref = 0.0;
  for (const atlas::TexelSample& t : raster.samples) {
    const double l = luminance(estimate.rgb(t.x, t.y));
    const double r = luminance(reference.rgb(t.x, t.y));
    e2 += (l - r) * (l - r);
    sum += l;
    sum_ref += r;
  }
  const double n = static_cast<double>(raster.covered());
  return {std::sqrt(e2 / n) / (sum_ref / n), sum / n};
}

// The reference's own relative RMSE as the baker estimates it: √(mean variance) / mean L.
double own_noise(const atlas::TexelRaster& raster, const bake::LightmapBake& bake) {
  double variance = 0.0, sum = 0.0;
  for (const atlas::TexelSample& t : raster.samples) {
    variance += bake.variance.pixel(t.x, t.y)[0];
    sum += luminance(bake.layers[0].rgb(t.x, t.y));
  }
  const double n = static_cast<double>(raster.covered());
  return std::sqrt(variance / n) / (sum / n);
}

bool same_covered_texels(const atlas::TexelRaster& raster, const Image& a, const Image& b) {
  return std::all_of(
      raster.samples.begin(), raster.samples.end(), [&](const atlas::TexelSample& t) {
        return std::equal(a.pixel(t.x, t.y), a.pixel(t.x, t.y) + 3, b.pixel(t.x, t.y));
      });
}

nlohmann::json bench_scene(const std::string& name, const LightmapArgs& a) {
  Scene scene = load_scene(name);
  const bool sky_added = add_sky_if_unlit(scene);
  const atlas::Atlas atlas = atlas::chart_scene(scene, {.resolution = atlas_resolution(a, name)});
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atlas.width, atlas.height);
  if (raster.covered() == 0) throw Error(fmt::format("{}: the atlas covers no texel", name));

  // The path tracer renders about as many pixels as there are texels; its max_bounces counts
  // the camera vertex's scattering, which the baker's texel does not (lightmap_baker.h).
  const int side = std::max(1, static_cast<int>(std::lround(std::sqrt(double(raster.covered())))));
  const Camera camera = scene_camera(scene, 1.0f);
  PathIntegrator integrator(
      Params(nlohmann::json{{"max_bounces", a.max_bounces + 1}}, "illum-bench lightmap"));
  RenderOptions render;
  render.width = render.height = side;
  render.spp = a.spp;
  render.seed = a.seed;
  render.threads = a.threads;
  render.progress = false;

  std::printf(
      "\n%s: %zu triangles%s, atlas %dx%d (%d charts, texel %.4g m, %zu texels), "
      "path image %dx%d\n",
      scene.name.c_str(), scene.triangle_count(), sky_added ? " (white sky added)" : "",
      atlas.width, atlas.height, atlas.chart_count, double(atlas.texel_size), raster.covered(),
      side, side);

  // 1. Throughput, interleaved rounds. Every round's bake is the same raw estimate (a texel
  // depends only on seed, position, spp and scene), kept for part 2.
  const bake::LightmapBakeOptions raw_options = bake_options(a, a.spp, a.seed);
  Throughput baker, path;
  bake::LightmapBake raw;
  bool deterministic = true;
  for (int r = 0; r < a.repeats; ++r) {
    bake::LightmapBake b = bake::bake_lightmap(scene, tracer, raster, raw_options);
    baker.add(b.seconds, static_cast<int64_t>(b.texels) * a.spp, b.rays);
    if (r > 0)
      deterministic = deterministic && same_covered_texels(raster, b.layers[0], raw.layers[0]);
    raw = std::move(b);
    integrator.render(tracer, camera, render);
    const PathIntegrator::Stats& st = integrator.stats();
    path.add(st.render.seconds, st.render.samples, st.rays);
  }
  const double rays_ratio = median(baker.rays_per_s) / median(path.rays_per_s);
  const double rays_ratio_paired = paired_ratio(baker.rays_per_s, path.rays_per_s);
  const double samples_ratio = median(baker.samples_per_s) / median(path.samples_per_s);
  const double samples_ratio_paired = paired_ratio(baker.samples_per_s, path.samples_per_s);
  std::printf("  %-22s %9s %12s %10s %9s\n", "throughput", "seconds", "Msamples/s", "Mrays/s",
              "rays/smp");
  for (const auto& [label, t] : {std::pair{"baker (plain, all)", &baker}, {"path tracer", &path}})
    std::printf("  %-22s %9.3f %12.3f %10.3f %9.2f\n", label, median(t->seconds),
                median(t->samples_per_s) * 1e-6, median(t->rays_per_s) * 1e-6,
                t->rays_per_sample());
  std::printf("  baker/path: rays/s %.3f (paired %.3f), samples/s %.3f (paired %.3f)%s\n",
              rays_ratio, rays_ratio_paired, samples_ratio, samples_ratio_paired,
              deterministic ? "" : "  WARNING: repeated bakes differ");

  // 2. Denoising the raw bake exactly as bake_lightmap does (plain guide = layer 0's
  // luminance, luminance_sigma = denoise_strength), timed over R copies.
  bake::LightmapDenoiseOptions denoise_options;
  denoise_options.luminance_sigma = raw_options.denoise_strength;
  std::vector<Image> denoised;
  std::vector<double> denoise_seconds;
  for (int r = 0; r < a.repeats; ++r) {
    denoised = raw.layers;
    const auto t0 = std::chrono::steady_clock::now();
    bake::denoise_lightmap(scene, raster, denoised, raw.variance, {1.0f}, denoise_options);
    denoise_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  // The baker's own denoised bake must give the very same texels, or this bench measures
  // something else than `illum bake` does.
  bake::LightmapBakeOptions denoised_options = raw_options;
  denoised_options.denoise = true;
  const bake::LightmapBake baker_denoised =
      bake::bake_lightmap(scene, tracer, raster, denoised_options);
  const bool matches_baker = same_covered_texels(raster, baker_denoised.layers[0], denoised[0]);

  // An independent reference: another seed, so its noise is not the raw bake's.
  const int ref_spp = reference_spp(a, name);
  const bake::LightmapBake reference =
      bake::bake_lightmap(scene, tracer, raster, bake_options(a, ref_spp, a.seed + 1));
  const double reference_noise = own_noise(raster, reference);
  const MapError raw_error = compare(raster, raw.layers[0], reference.layers[0]);
  const MapError denoised_error = compare(raster, denoised[0], reference.layers[0]);
  const double mean_ratio = denoised_error.mean / raw_error.mean;
  std::printf("  denoiser: %d spp against a %d-spp reference (%.2f s; its own noise %.2f%%)\n",
              a.spp, ref_spp, reference.seconds, 100.0 * reference_noise);
  std::printf(
      "  relative RMSE raw %.2f%%, denoised %.2f%% (%.2fx lower); mean denoised/raw %.4f;"
      " denoise %.3f s (in the baker %.3f s)%s\n",
      100.0 * raw_error.relative_rmse, 100.0 * denoised_error.relative_rmse,
      raw_error.relative_rmse / denoised_error.relative_rmse, mean_ratio, median(denoise_seconds),
      baker_denoised.denoise_seconds,
      matches_baker ? "" : "  WARNING: differs from the baker's denoised map");

  return {{"scene", scene.name},
          {"scene_arg", name},
          {"triangles", scene.triangle_count()},
          {"sky_added", sky_added},
          {"atlas",
           {{"resolution", atlas.width},
            {"charts", atlas.chart_count},
            {"texel_size", atlas.texel_size},
            {"texels", raster.covered()}}},
          {"throughput",
           {{"path_image", side},
            {"path_max_bounces", a.max_bounces + 1},
            {"baker", baker.to_json()},
            {"path", path.to_json()},
            {"rays_per_s_ratio", rays_ratio},
            {"rays_per_s_ratio_paired", rays_ratio_paired},
            {"samples_per_s_ratio", samples_ratio},
            {"samples_per_s_ratio_paired", samples_ratio_paired},
            {"bakes_identical", deterministic}}},
          {"denoise",
           {{"reference_spp", ref_spp},
            {"reference_seed", a.seed + 1},
            {"reference_seconds", reference.seconds},
            {"reference_noise", reference_noise},
            {"rmse_raw", raw_error.relative_rmse},
            {"rmse_denoised", denoised_error.relative_rmse},
            {"rmse_ratio", raw_error.relative_rmse / denoised_error.relative_rmse},
            {"mean_ratio", mean_ratio},
            {"strength", denoise_options.luminance_sigma},
            {"seconds", median(denoise_seconds)},
            {"seconds_runs", denoise_seconds},
            {"baker_seconds", baker_denoised.denoise_seconds},
            {"matches_baker", matches_baker}}}};
}

}  // namespace

int run_lightmap(SuiteArgs args) {
  CLI::App app("Light-map baker: throughput vs the path tracer, denoiser error and cost",
               "illum-bench lightmap");
  LightmapArgs a;
  app.add_option("--scene", a.scenes, "built-in scene names or scene files (default: cornell)");
  app.add_option("--resolution", a.resolution,
                 "atlas side in texels (0: 256 for cornell, 512 otherwise)")
      ->check(CLI::Range(0, 16384));
  app.add_option("--spp", a.spp, "samples per texel of the timed and denoised bakes")
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--reference-spp", a.reference_spp,
                 "samples per texel of the reference (0: 1024 for cornell, 128 otherwise)")
      ->check(CLI::Range(0, 1 << 20));
  app.add_option("--max-bounces", a.max_bounces, "baker's bounces after the texel")
      ->check(CLI::Range(0, 1023));
  app.add_option("--repeats", a.repeats, "timed rounds (median reported)")
      ->check(CLI::Range(1, 100));
  app.add_option("--threads", a.threads, "TBB threads (0 = all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--seed", a.seed, "sampler seed (the reference uses seed + 1)");
  app.add_option("--json", a.json_path, "write the results here");
  if (!parse_args(app, args)) return 0;
  check_output_folder(a.json_path);
  const int thread_count = a.threads > 0 ? a.threads : ThreadLimit::hardware_threads();

  std::printf("lightmap: %d spp, max_bounces %d (path tracer %d), %d threads, median of %d\n",
              a.spp, a.max_bounces, a.max_bounces + 1, thread_count, a.repeats);
  nlohmann::json results = nlohmann::json::array();
  for (const std::string& name : a.scenes) results.push_back(bench_scene(name, a));
  if (!a.json_path.empty())
    write_json(a.json_path, {{"suite", "lightmap"},
                             {"spp", a.spp},
                             {"max_bounces", a.max_bounces},
                             {"repeats", a.repeats},
                             {"seed", a.seed},
                             {"threads", thread_count},
                             {"scenes", results},
                             {"machine", machine_info()}});
  return 0;
}

}  // namespace illum::bench
