// `illum-bench path [SCENES...]`: path-tracing throughput — camera samples per second and
// rays (closest-hit + shadow) per second — on built-in scenes (default: cornell, sibenik).
// Scenes without any light (Sibenik ships none) get a uniform white sky (radiance 1) so the
// paths do the work a lit scene would.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/render/path_integrator.h"
#include "illum/render/render_setup.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

int run_path(SuiteArgs args) {
  CLI::App app("Path-tracing throughput: samples/s and rays/s", "illum-bench path");
  std::vector<std::string> scenes;
  std::string json_path;
  int width = 256, height = 256, spp = 16, threads = 0, max_bounces = 8, repeats = 3;
  uint64_t seed = 1;
  app.add_option("scenes", scenes,
                 "built-in scene names or scene files (default: cornell sibenik)");
  app.add_option("--width", width, "image width")->check(CLI::Range(1, 16384));
  app.add_option("--height", height, "image height")->check(CLI::Range(1, 16384));
  app.add_option("--spp", spp, "samples per pixel")->check(CLI::Range(1, 1 << 20));
  app.add_option("--max-bounces", max_bounces, "path length limit")->check(CLI::Range(0, 1024));
  app.add_option("--repeats", repeats, "renders per scene (median reported)")
      ->check(CLI::Range(1, 100));
  app.add_option("--threads", threads, "TBB threads (0 = all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--seed", seed, "sampler seed");
  app.add_option("--json", json_path, "write the results here");
  if (!parse_args(app, args)) return 0;
  if (scenes.empty()) scenes = {"cornell", "sibenik"};
  check_output_folder(json_path);
  const int thread_count = threads > 0 ? threads : ThreadLimit::hardware_threads();

  nlohmann::json results = nlohmann::json::array();
  std::printf("path: %dx%d, %d spp, max_bounces %d, %d threads, median of %d\n", width, height, spp,
              max_bounces, thread_count, repeats);
  std::printf("  %-12s %10s %10s %12s %12s %10s\n", "scene", "triangles", "seconds", "Msamples/s",
              "Mrays/s", "rays/smp");
  for (const std::string& name : scenes) {
    Scene scene = load_scene(name);
    const bool added_sky = add_sky_if_unlit(scene);
    const RayTracer tracer(scene);
    const Camera camera =
        scene_camera(scene, static_cast<float>(width) / static_cast<float>(height));
    Params params(nlohmann::json{{"max_bounces", max_bounces}}, "illum-bench path");
    PathIntegrator integrator(params);
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.spp = spp;
    options.seed = seed;
    options.threads = threads;
    options.progress = false;
    std::vector<double> seconds, samples_per_s, rays_per_s;
    int64_t rays = 0, samples = 0;
    for (int r = 0; r < repeats; ++r) {
      integrator.render(tracer, camera, options);
      const PathIntegrator::Stats& st = integrator.stats();
      seconds.push_back(st.render.seconds);
      samples_per_s.push_back(static_cast<double>(st.render.samples) / st.render.seconds);
      rays_per_s.push_back(static_cast<double>(st.rays) / st.render.seconds);
      rays = st.rays;
      samples = st.render.samples;
    }
    const double rays_per_sample = static_cast<double>(rays) / static_cast<double>(samples);
    std::printf("  %-12s %10zu %10.3f %12.3f %12.3f %10.2f%s\n", scene.name.c_str(),
                scene.triangle_count(), median(seconds), median(samples_per_s) * 1e-6,
                median(rays_per_s) * 1e-6, rays_per_sample, added_sky ? "  (white sky added)" : "");
    results.push_back({{"scene", scene.name},
                       {"scene_arg", name},
                       {"triangles", scene.triangle_count()},
                       {"sky_added", added_sky},
                       {"seconds", median(seconds)},
                       {"seconds_runs", seconds},
                       {"samples", samples},
                       {"rays", rays},
                       {"samples_per_s", median(samples_per_s)},
                       {"rays_per_s", median(rays_per_s)},
                       {"rays_per_sample", rays_per_sample}});
  }
  if (!json_path.empty()) {
    nlohmann::json j;
    j["suite"] = "path";
    j["width"] = width;
    j["height"] = height;
    j["spp"] = spp;
    j["max_bounces"] = max_bounces;
    j["repeats"] = repeats;
    j["seed"] = seed;
    j["threads"] = thread_count;
    j["scenes"] = results;
    j["machine"] = machine_info();
    write_json(json_path, j);
  }
  return 0;
}

}  // namespace illum::bench
