// `illum-bench probes`: irradiance-probe bake time (bake/probe_baker.h) per 1000 probes on
// built-in scenes (default: cornell, sibenik), on the default grid (the scene's longest side
// over 16) or --spacing, at --spp sphere samples per probe: the whole bake_probes call
// (validity rays included) timed once per scene after a warm-up of the same grid at 1 spp.
// With --images DIR it also writes probes_leak.png (docs/probes.md): the leak test's two rooms
// (tests/bake/probes_test.cpp), a slice through the probe grid's lookups without and with the
// visibility test.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "illum/bake/probe_baker.h"
#include "illum/bake/probe_lookup.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/parallel.h"
#include "illum/core/sh.h"
#include "illum/core/tonemap.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

// The leak test's scene: rooms [−2, 0] and [0, 2] × [0, 2] × [−1, 1] (x, y, z), a closed wall
// 5 cm thick between them, a point light in the room at x > 0; Lambert 0.5.
Scene two_rooms() {
  Scene s;
  s.name = "two-rooms";
  Material m;
  m.albedo = Color(0.5f);
  s.materials.push_back(m);
  auto box = [&](vec3 lo, vec3 hi, bool inward) {
    Mesh mesh;
    const vec3 v[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                       {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                       {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    const int f[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                         {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 2, 6, 5}};
    const vec3 c = 0.5f * (lo + hi);
    const int halves[2][3] = {{0, 1, 2}, {0, 2, 3}};  // a quad's two triangles
    for (const auto& q : f)
      for (const auto& t : halves) {
        vec3 a = v[q[t[0]]], b = v[q[t[1]]], d = v[q[t[2]]];
        const bool faces_in = glm::dot(glm::cross(b - a, d - a), c - (a + b + d) / 3.0f) > 0.0f;
        if (faces_in != inward) std::swap(b, d);
        for (const vec3& p : {a, b, d}) {
          mesh.indices.push_back(uint32_t(mesh.positions.size()));
          mesh.positions.push_back(p);
        }
      }
    s.meshes.push_back(std::move(mesh));
    Instance inst;
    inst.mesh = int(s.meshes.size()) - 1;
    s.instances.push_back(inst);
  };
  box(vec3(-2.0f, 0.0f, -1.0f), vec3(2.0f, 2.0f, 1.0f), true);
  box(vec3(-0.025f, 0.0f, -1.0f), vec3(0.025f, 2.0f, 1.0f), false);
  Light light;
  light.type = LightType::kPoint;
  light.position = vec3(0.6f, 1.2f, 0.1f);
  light.intensity = Color(5.0f);
  s.lights.push_back(light);
  return s;
}

// Two panels over the slice z = 0.1, x ∈ [−1, 1] right, y ∈ [0, 2] up: the mean irradiance over
// normals (E_0·Y_00) looked up with validity weights only, and with the visibility test; the wall
// grey.
void write_leak_image(const std::string& folder, int spp) {
  const Scene scene = two_rooms();
  const RayTracer tracer(scene);
  bake::ProbeBakeOptions options;
  options.spacing = 0.5f;  // coarse, so the cell across the wall shows
  options.spp = spp;
  options.progress = false;
  bake::ProbeBake baked = bake::bake_probes(scene, tracer, options);
  baked::ProbeSet set;
  set.grid = baked.grid;
  set.probes = std::move(baked.probes);
  const int w = 300, h = 300, gap = 6;
  Image image(2 * w + gap, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < image.width(); ++x)
      image.set_rgb(x, y, Color(100.0f));  // white between the panels
  for (int panel = 0; panel < 2; ++panel)
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        const vec3 p(-1.0f + 2.0f * (float(px) + 0.5f) / float(w),
                     2.0f - 2.0f * (float(py) + 0.5f) / float(h), 0.1f);
        Color c(0.3f);
        if (std::abs(p.x) > 0.025f) {
          const bake::ProbeSample s = bake::lookup_probes(set, p, panel == 1 ? &tracer : nullptr);
          c = Color(s.irradiance[0], s.irradiance[1], s.irradiance[2]) * float(sh::kY00);
        }
        image.set_rgb(panel * (w + gap) + px, py, c);
      }
  const std::string path = folder + "/probes_leak.png";
  write_image(path, tone_mapped(image, ToneMapper::kReinhard, 0.15f));
  std::printf("wrote %s\n", path.c_str());
}

}  // namespace

int run_probes(SuiteArgs args) {
  std::vector<std::string> scenes;
  int spp = 64, threads = 0;
  float spacing = 0.0f;
  std::string json_path, images;
  CLI::App app("irradiance-probe bake time per 1000 probes", "illum-bench probes");
  app.add_option("--scenes", scenes, "built-in scene names or files (default: cornell sibenik)");
  app.add_option("--spp", spp, "sphere samples per probe")
      ->check(CLI::Range(1, bake::kMaxProbeSpp))
      ->capture_default_str();
  app.add_option("--spacing", spacing, "metres between probes (0: the bake's default)")
      ->check(CLI::Range(0.0f, 1e6f));
  app.add_option("--threads", threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--images", images, "folder for probes_leak.png (docs/probes.md)");
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
  if (!images.empty()) write_leak_image(images, spp);
  if (!json_path.empty())
    write_json(json_path, {{"suite", "probes"}, {"results", results}, {"machine", machine_info()}});
  return 0;
}

}  // namespace illum::bench
