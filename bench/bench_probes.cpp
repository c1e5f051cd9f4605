// `illum-bench probes`: irradiance-probe bake time (bake/probe_baker.h) per 1000 probes on
// built-in scenes (default: cornell, sibenik), on the default grid (the scene's longest side
// over 16) or --spacing, at --spp sphere samples per probe: the whole bake_probes call
// (validity rays included) timed once per scene after a warm-up of the same grid at 1 spp.
#include <chrono>
#include <cstdio>
#include <vector>

#include "illum/bake/probe_baker.h"
#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

int run_probes(SuiteArgs args) {
  std::vector<std::string> scenes;
  int spp = 64, threads = 0;
  float spacing = 0.0f;
  std::string json_path;
  CLI::App app("irradiance-probe bake time per 1000 probes", "illum-bench probes");
  app.add_option("--scenes", scenes, "built-in scene names or files (default: cornell sibenik)");
  app.add_option("--spp", spp, "sphere samples per probe")
      ->check(CLI::Range(1, bake::kMaxProbeSpp))
      ->capture_default_str();
  app.add_option("--spacing", spacing, "metres between probes (0: the bake's default)")
      ->check(CLI::Range(0.0f, 1e6f));
  app.add_option("--threads", threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--json", json_path, "write the results to this JSON file");
  if (!parse_args(app, args)) return 0;
  if (scenes.empty()) scenes = {"cornell", "sibenik"};

  ThreadLimit limit(threads);
  nlohmann::json results = nlohmann::json::array();
  for (const std::string& name : scenes) {
    const Scene scene = bake::static_part(load_scene(name));
    const RayTracer tracer(scene);
    bake::ProbeBakeOptions options;
    options.spacing = spacing;
    options.spp = 1;
    options.threads = threads;
    options.progress = false;
    bake::bake_probes(scene, tracer, options);  // warm-up: caches, thread pool
    options.spp = spp;
    const auto t0 = std::chrono::steady_clock::now();
    const bake::ProbeBake baked = bake::bake_probes(scene, tracer, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double probes = double(baked.grid.count());
    const double per_1000 = seconds / probes * 1000.0;
    const double mrays = double(baked.stats.rays) / seconds * 1e-6;
    std::printf(
        "%s: %dx%dx%d probes (spacing %.4g m, %lld invalid), %d spp: %.3fs, %.3fs per "
        "1000 probes, %.2f Mrays/s\n",
        scene.name.c_str(), baked.grid.size.x, baked.grid.size.y, baked.grid.size.z,
        double(baked.grid.spacing), static_cast<long long>(baked.stats.invalid), spp, seconds,
        per_1000, mrays);
    results.push_back({{"scene", scene.name},
                       {"probes", baked.grid.count()},
                       {"spacing", baked.grid.spacing},
                       {"spp", spp},
                       {"invalid", baked.stats.invalid},
                       {"seconds", seconds},
                       {"seconds_per_1000_probes", per_1000},
                       {"mrays_per_second", mrays}});
  }
  if (!json_path.empty())
    write_json(json_path, {{"suite", "probes"}, {"results", results}, {"machine", machine_info()}});
  return 0;
}

}  // namespace illum::bench
