// `illum-bench atlas`: what the light-map atlas (atlas/atlas.h) makes of a scene and how long
// it takes: charts, utilisation (uv1 area of the triangles over the atlas's), texel density
// and stretch against the nominal density (atlas/atlas_report.h), the conservative texel
// coverage, and the charting + packing time (wall and CPU seconds, with the load average,
// because the development machine is shared).
//
// `--synthetic N` builds a deterministic scene of about N triangles instead of loading one:
// a tessellated terrain (half the triangles, a smooth heightfield 200 m across) and many
// small spheres on it (the other half, 720 triangles each, radii 0.3–1.5 m), every sphere
// its own mesh and instance, as a level full of props would be.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "illum/atlas/atlas.h"
#include "illum/atlas/atlas_report.h"
#include "illum/atlas/texel_raster.h"
#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/scene/load.h"
#include "illum/scene/scene.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct AtlasArgs {
  std::vector<std::string> scenes;
  int64_t synthetic = 0;  // triangles of the synthetic scene (0: none)
  int resolution = 1024;
  float texel_size = 0.0f;
  int threads = 0;
  int repeats = 1;
  bool regenerate_uv1 = false;
  std::string json_path;
};

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The 1-minute load average (all processes of the machine, not only this one).
double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = -1.0;
  in >> load;
  return load;
}

// A sphere of `stacks` × `slices` quads (triangles at the poles), radius r, centre c.
Mesh sphere_mesh(const std::string& name, vec3 centre, float radius, int stacks, int slices) {
  Mesh mesh;
  mesh.name = name;
  auto add = [&](vec3 n) {
    mesh.positions.push_back(centre + radius * n);
    mesh.normals.push_back(n);
  };
  add(vec3(0.0f, 1.0f, 0.0f));
  for (int i = 1; i < stacks; ++i) {
    const float theta = kPi * float(i) / float(stacks);
    for (int j = 0; j < slices; ++j) {
      const float phi = 2.0f * kPi * float(j) / float(slices);
      add(vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  }
  add(vec3(0.0f, -1.0f, 0.0f));
  const uint32_t bottom = uint32_t(mesh.positions.size() - 1);
  auto ring = [&](int i, int j) { return uint32_t(1 + (i - 1) * slices + (j % slices)); };
  for (int j = 0; j < slices; ++j) {
    mesh.indices.insert(mesh.indices.end(), {0u, ring(1, j + 1), ring(1, j)});
    mesh.indices.insert(mesh.indices.end(), {bottom, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
  }
  for (int i = 1; i + 1 < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const uint32_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  return mesh;
}

float terrain_height(float x, float z) {
  return 3.0f * std::sin(0.05f * x) * std::cos(0.07f * z) + 0.8f * std::sin(0.31f * x + 0.17f * z);
}

Scene synthetic_scene(int64_t triangles) {
  Scene scene;
  scene.name = fmt::format("synthetic-{}", triangles);
  scene.materials.emplace_back();
  constexpr float kSide = 200.0f;
  constexpr int kStacks = 16, kSlices = 24;  // 2·24 + 2·24·14 = 720 triangles
  constexpr int64_t kSphereTriangles = 2 * kSlices * (kStacks - 1);
  const int n = std::max(1, int(std::lround(std::sqrt(double(triangles) / 4.0))));  // quads a side
  Mesh terrain;
  terrain.name = "terrain";
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const float x = kSide * (float(i) / float(n) - 0.5f),
                  z = kSide * (float(j) / float(n) - 0.5f);
      terrain.positions.push_back(vec3(x, terrain_height(x, z), z));
      terrain.normals.push_back(vec3(0.0f, 1.0f, 0.0f));  // the atlas uses face normals
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const uint32_t a = uint32_t(i * (n + 1) + j), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      terrain.indices.insert(terrain.indices.end(), {a, b, d, a, d, c});
    }
  scene.meshes.push_back(std::move(terrain));
  const int64_t spheres = std::max<int64_t>(0, (triangles - 2 * int64_t(n) * n) / kSphereTriangles);
  uint64_t state = 0x9E3779B97F4A7C15ull;  // a fixed LCG: the same scene every time
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return float(state >> 40) / float(1 << 24);
  };
  for (int64_t k = 0; k < spheres; ++k) {
    const float x = kSide * (next() - 0.5f), z = kSide * (next() - 0.5f);
    const float r = 0.3f + 1.2f * next();
    scene.meshes.push_back(sphere_mesh(fmt::format("sphere{}", k),
                                       vec3(x, terrain_height(x, z) + r, z), r, kStacks, kSlices));
  }
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    Instance instance;
    instance.name = scene.meshes[m].name;
    instance.mesh = int(m);
    scene.instances.push_back(instance);
  }
  return scene;
}

nlohmann::json density_json(const atlas::DensityStats& d) {
  return {{"triangles", d.triangles},           {"world_area_m2", d.world_area},
          {"nominal_texels", d.nominal_texels}, {"uv_texels", d.uv_texels},
          {"mean_density", d.mean_density},     {"min_density", d.min_density},
          {"max_density", d.max_density},       {"rms_l2_stretch", d.rms_l2_stretch},
          {"max_anisotropy", d.max_anisotropy}};
}

nlohmann::json bench_scene(Scene scene, const AtlasArgs& a) {
  atlas::make_meshes_unique(scene);
  atlas::AtlasOptions options;
  options.resolution = a.resolution;
  options.texel_size = a.texel_size;
  options.reuse_uv1 = !a.regenerate_uv1;
  std::vector<double> wall, cpu;
  atlas::Atlas built;
  const double load_before = load_average();
  for (int r = 0; r < a.repeats; ++r) {
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    built = atlas::build_atlas(scene, options);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    cpu.push_back(cpu_seconds() - cpu0);
  }
  const double load_after = load_average();
  atlas::apply_atlas(scene, built);
  const atlas::AtlasStats stats = atlas::measure_atlas(scene, built);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, built.width, built.height);
  const double atlas_texels = double(built.width) * built.height;
  std::printf(
      "%s: %zu triangles, %zu meshes; %dx%d atlas, %d charts, texel %.4g m; utilisation %.1f%% "
      "(conservative coverage %.1f%%); density mean %.3f [%.3f, %.3f], rms L2 stretch %.3f; "
      "%.2f s wall, %.2f s CPU (median of %d; load %.2f → %.2f)\n",
      scene.name.c_str(), scene.triangle_count(), scene.meshes.size(), built.width, built.height,
      built.chart_count, double(built.texel_size), 100.0 * stats.utilisation,
      100.0 * double(raster.covered()) / atlas_texels, stats.all.mean_density,
      stats.all.min_density, stats.all.max_density, stats.all.rms_l2_stretch, median(wall),
      median(cpu), a.repeats, load_before, load_after);
  return {{"scene", scene.name},
          {"triangles", scene.triangle_count()},
          {"meshes", scene.meshes.size()},
          {"resolution", built.width},
          {"charts", built.chart_count},
          {"texel_size", built.texel_size},
          {"chart_rectangle_share", stats.chart_texels / atlas_texels},
          {"utilisation", stats.utilisation},
          {"covered_texels", raster.covered()},
          {"covered_share", double(raster.covered()) / atlas_texels},
          {"density", density_json(stats.all)},
          {"seconds", median(wall)},
          {"seconds_runs", wall},
          {"cpu_seconds", median(cpu)},
          {"cpu_seconds_runs", cpu},
          {"load_average_before", load_before},
          {"load_average_after", load_after}};
}

}  // namespace

int run_atlas(SuiteArgs args) {
  CLI::App app("charts, utilisation, texel density and stretch of the light-map atlas; time",
               "illum-bench atlas");
  AtlasArgs a;
  app.add_option("--scene", a.scenes, "built-in scene names or scene files");
  app.add_option("--synthetic", a.synthetic,
                 "also a deterministic synthetic scene of about this many triangles (terrain "
                 "and small spheres)")
      ->check(CLI::Range(int64_t(0), int64_t(1) << 27));
  app.add_option("--resolution", a.resolution, "atlas side in texels")
      ->check(CLI::Range(atlas::kMinResolution, atlas::kMaxResolution));
  app.add_option("--texel-size", a.texel_size, "metres per texel (0: the finest that fits)")
      ->check(CLI::Range(0.0f, 1e6f));
  app.add_option("--threads", a.threads, "TBB threads (0 = all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--repeats", a.repeats, "timed builds (median reported)")
      ->check(CLI::Range(1, 100));
  app.add_flag("--regenerate-uv1", a.regenerate_uv1,
               "chart every mesh anew, even one whose own UV1 is valid");
  app.add_option("--json", a.json_path, "write the results here");
  if (!parse_args(app, args)) return 0;
  if (a.scenes.empty() && a.synthetic == 0)
    throw Error("illum-bench atlas: give --scene NAME or --synthetic TRIANGLES");
  check_output_folder(a.json_path);
  const ThreadLimit limit(a.threads);
  const int thread_count = a.threads > 0 ? a.threads : ThreadLimit::hardware_threads();
  std::printf("atlas: %dx%d, %d threads\n", a.resolution, a.resolution, thread_count);
  nlohmann::json results = nlohmann::json::array();
  for (const std::string& name : a.scenes) results.push_back(bench_scene(load_scene(name), a));
  if (a.synthetic > 0) results.push_back(bench_scene(synthetic_scene(a.synthetic), a));
  if (!a.json_path.empty())
    write_json(a.json_path, {{"suite", "atlas"},
                             {"resolution", a.resolution},
                             {"texel_size", a.texel_size},
                             {"threads", thread_count},
                             {"repeats", a.repeats},
                             {"scenes", results},
                             {"machine", machine_info()}});
  return 0;
}

}  // namespace illum::bench
