// `illum-bench radiosity`: time to equal error of the radiosity baker (bake/radiosity_baker.h)
// against the path-traced baker (bake/lightmap_baker.h, denoised as `illum bake` does), both
// measured against one long path-traced bake of the same atlas (raw, not denoised, so the
// reference has no filter bias; its own noise is printed). The path baker runs at doubling
// spp until its error drops below radiosity's; the time at equal error is interpolated in
// log(time)–log(error) between the two bracketing runs. Ratio = path time / radiosity time at
// radiosity's error. With --images DIR it writes the maps in atlas space (radiosity, path at
// equal error, reference, and radiosity's relative error as a heat map) as PNGs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/radiosity_baker.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/parallel.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct RadiosityArgs {
  std::string scene = "cornell";
  int resolution = 48;
  int reference_spp = 4096;
  double threshold = bake::kDefaultRadiosityThreshold;
  double relative_threshold = bake::kDefaultRadiosityRelativeThreshold;
  int max_spp = 4096;
  std::vector<double> cluster_ratios{bake::kDefaultClusterRatio};
  int threads = 0;
  std::string images;  // folder for the PNGs, "" = none
  std::string json_path;
};

// Relative RMSE of layer 0's luminance over covered texels: √(mean (L − L_ref)²) / mean L_ref.
double relative_rmse(const atlas::TexelRaster& raster, const Image& estimate,
                     const Image& reference) {
  double e2 = 0.0, sum_ref = 0.0;
  for (const atlas::TexelSample& t : raster.samples) {
    const double l = luminance(estimate.rgb(t.x, t.y)), r = luminance(reference.rgb(t.x, t.y));
    e2 += (l - r) * (l - r);
    sum_ref += r;
  }
  const double n = double(raster.covered());
  return std::sqrt(e2 / n) / (sum_ref / n);
}

// Nearest-neighbour enlargement so single texels stay visible in the docs.
Image enlarge(const Image& image, int factor) {
  Image out(image.width() * factor, image.height() * factor, 3);
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) out.set_rgb(x, y, image.rgb(x / factor, y / factor));
  return out;
}

// |R − ref| / ref per covered texel on a black→red→yellow→white ramp reaching white at
// `full` (uncovered texels dark blue).
Image heat_map(const atlas::TexelRaster& raster, const Image& estimate, const Image& reference,
               double full) {
  Image out(raster.width, raster.height, 3);
  for (int y = 0; y < raster.height; ++y)
    for (int x = 0; x < raster.width; ++x) out.set_rgb(x, y, Color(0.0f, 0.0f, 0.08f));
  for (const atlas::TexelSample& t : raster.samples) {
    const double r = luminance(reference.rgb(t.x, t.y));
    const double e = r > 0.0 ? std::abs(luminance(estimate.rgb(t.x, t.y)) - r) / r : 0.0;
    const float v = float(std::clamp(e / full, 0.0, 1.0)) * 3.0f;
    out.set_rgb(t.x, t.y,
                Color(std::min(v, 1.0f), std::clamp(v - 1.0f, 0.0f, 1.0f),
                      std::clamp(v - 2.0f, 0.0f, 1.0f)));
  }
  return out;
}

}  // namespace

int run_radiosity(SuiteArgs args) {
  RadiosityArgs a;
  CLI::App app("Radiosity light-maps: time to equal error against the path-traced baker",
               "illum-bench radiosity");
  app.add_option("--scene", a.scene, "scene (built-in name or file)")->capture_default_str();
  app.add_option("--resolution", a.resolution, "atlas side in texels")
      ->check(CLI::Range(16, 4096))
      ->capture_default_str();
  app.add_option("--reference-spp", a.reference_spp, "spp of the reference path bake")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  app.add_option("--relative-threshold", a.relative_threshold,
                 "radiosity's mean relative unshot stop (1: off, the total rule alone)")
      ->check(CLI::Range(1e-9, 1.0));
  app.add_option("--threshold", a.threshold, "radiosity convergence threshold")
      ->check(CLI::Range(1e-9, 0.999))
      ->capture_default_str();
  app.add_option("--max-spp", a.max_spp,
                 "largest spp tried for the path baker (0: no time-to-equal-error search)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
  app.add_option("--cluster-ratio", a.cluster_ratios,
                 "receiver clusters share visibility at size/distance ≤ this (0: a ray per "
                 "receiver, the unclustered bake); several values: one bake each")
      ->check(CLI::Range(0.0, 0.5))
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--threads", a.threads, "worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096));
  app.add_option("--images", a.images, "folder for the comparison PNGs");
  app.add_option("--json", a.json_path, "write the results to this JSON file");
  if (!parse_args(app, args)) return 0;
  check_output_folder(a.json_path);
  if (!a.images.empty()) check_output_folder(a.images + "/x.png");

  ThreadLimit limit(a.threads);
  Scene scene = load_scene(a.scene);
  const atlas::Atlas atlas = atlas::chart_scene(scene, {.resolution = a.resolution});
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atlas.width, atlas.height);

  bake::LightmapBakeOptions path;
  path.progress = false;
  path.dilate = 0;
  path.spp = a.reference_spp;
  path.seed = 1000;  // independent of the timed bakes' seed 0
  const bake::LightmapBake reference = bake::bake_lightmap(scene, tracer, raster, path);
  double variance = 0.0, mean = 0.0;
  for (const atlas::TexelSample& t : raster.samples) {
    variance += reference.variance.pixel(t.x, t.y)[0];
    mean += luminance(reference.layers[0].rgb(t.x, t.y));
  }
  const double reference_noise =
      std::sqrt(variance / double(raster.covered())) / (mean / double(raster.covered()));

  std::printf("%s %dx%d, %zu texels; reference %d spp (own noise %.4f) %.1fs\n", scene.name.c_str(),
              raster.width, raster.height, raster.covered(), a.reference_spp, reference_noise,
              reference.seconds);
  // One radiosity bake per cluster ratio (the same atlas and reference); the time-to-equal-
  // error search and the images use the last.
  bake::RadiosityBakeOptions radiosity;
  radiosity.progress = false;
  radiosity.dilate = 0;
  radiosity.threshold = a.threshold;
  radiosity.relative_threshold = a.relative_threshold;
  nlohmann::json radiosity_runs = nlohmann::json::array();
  bake::RadiosityBake r;
  double radiosity_error = 0.0;
  for (const double ratio : a.cluster_ratios) {
    radiosity.cluster_ratio = float(ratio);
    r = bake::bake_radiosity(scene, tracer, raster, radiosity);
    radiosity_error = relative_rmse(raster, r.layers[0], reference.layers[0]);
    std::printf(
        "radiosity threshold %g, cluster ratio %g: %.3fs, %lld shots, %lld visibility rays "
        "(%.1f per shot), %lld shared clusters, relative RMSE %.4f; relative threshold %g: "
        "mean relative unshot %.4f, %lld shots for it\n",
        a.threshold, ratio, r.seconds, (long long)r.shots, (long long)r.visibility_rays,
        double(r.visibility_rays) / double(std::max<int64_t>(r.shots, 1)),
        (long long)r.shared_clusters, radiosity_error, a.relative_threshold, r.relative_unshot,
        (long long)r.relative_shots);
    std::fflush(stdout);
    radiosity_runs.push_back({{"cluster_ratio", ratio},
                              {"seconds", r.seconds},
                              {"shots", r.shots},
                              {"visibility_rays", r.visibility_rays},
                              {"shared_clusters", r.shared_clusters},
                              {"relative_unshot", r.relative_unshot},
                              {"relative_shots", r.relative_shots},
                              {"relative_rmse", radiosity_error}});
  }

  // Path bakes at doubling spp, denoised as the CLI bakes, until below radiosity's error.
  nlohmann::json runs = nlohmann::json::array();
  double prev_time = 0.0, prev_error = 0.0, equal_time = -1.0;
  bake::LightmapBake at_equal;
  path.seed = 0;
  path.denoise = true;
  for (int spp = 1; spp <= a.max_spp; spp *= 2) {
    path.spp = spp;
    bake::LightmapBake p = bake::bake_lightmap(scene, tracer, raster, path);
    const double error = relative_rmse(raster, p.layers[0], reference.layers[0]);
    std::printf("path %5d spp (denoised): %.3fs, relative RMSE %.4f\n", spp, p.seconds, error);
    runs.push_back({{"spp", spp}, {"seconds", p.seconds}, {"relative_rmse", error}});
    if (error <= radiosity_error) {
      // log-log interpolation between this run and the previous one
      if (prev_time > 0.0 && prev_error > error) {
        const double f = std::log(prev_error / radiosity_error) / std::log(prev_error / error);
        equal_time = std::exp(std::log(prev_time) + f * std::log(p.seconds / prev_time));
      } else {
        equal_time = p.seconds;
      }
      at_equal = std::move(p);
      break;
    }
    prev_time = p.seconds;
    prev_error = error;
  }
  nlohmann::json result = {{"scene", scene.name},
                           {"resolution", raster.width},
                           {"texels", raster.covered()},
                           {"reference_spp", a.reference_spp},
                           {"reference_noise", reference_noise},
                           {"radiosity_threshold", a.threshold},
                           {"radiosity_relative_threshold", a.relative_threshold},
                           {"radiosity_seconds", r.seconds},
                           {"radiosity_shots", r.shots},
                           {"radiosity_runs", radiosity_runs},
                           {"radiosity_relative_rmse", radiosity_error},
                           {"path_runs", runs},
                           {"machine", machine_info()}};
  if (equal_time > 0.0) {
    std::printf("time to equal error: path %.3fs / radiosity %.3fs = %.2f\n", equal_time, r.seconds,
                equal_time / r.seconds);
    result["path_seconds_at_equal_error"] = equal_time;
    result["ratio_path_over_radiosity"] = equal_time / r.seconds;
  } else if (a.max_spp > 0) {
    std::printf("the path baker did not reach radiosity's error within %d spp\n", a.max_spp);
  }
  if (!a.images.empty() && equal_time > 0.0) {
    const int k = std::max(1, 256 / raster.width);
    ImageWriteOptions png;
    png.exposure = 4.0f;  // Cornell's light-map values sit around 0.1–0.3
    write_image(a.images + "/radiosity_" + scene.name + "_radiosity.png", enlarge(r.layers[0], k),
                png);
    write_image(a.images + "/radiosity_" + scene.name + "_path.png", enlarge(at_equal.layers[0], k),
                png);
    write_image(a.images + "/radiosity_" + scene.name + "_reference.png",
                enlarge(reference.layers[0], k), png);
    ImageWriteOptions linear;
    linear.srgb = false;
    write_image(a.images + "/radiosity_" + scene.name + "_error.png",
                enlarge(heat_map(raster, r.layers[0], reference.layers[0], 0.2), k), linear);
  }
  if (!a.json_path.empty()) write_json(a.json_path, result);
  return 0;
}

}  // namespace illum::bench
