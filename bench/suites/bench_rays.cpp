// `illum-bench rays SCENE`: closest-hit throughput of incoherent rays through (a) illum's
// single-ray RayTracer::intersect, (b) its batch API and (c) a raw Embree rtcIntersect1
// loop over the same BVH, same rays, same threads. The three are interleaved round by
// round so that machine noise (other processes, turbo, thermal) hits them alike; the
// medians and their ratios are reported.
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"
#include "illum/core/sampling.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {
namespace {

// Work unit handed to one TBB task: large enough to amortise scheduling, small enough to
// balance two to sixteen threads over a million rays.
constexpr int64_t kChunk = 1024;

struct WorldTriangle {
  vec3 a, b, c;
};

std::vector<WorldTriangle> world_triangles(const Scene& scene) {
  std::vector<WorldTriangle> out;
  for (const Instance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    auto world = [&](uint32_t i) { return vec3(inst.transform * vec4(mesh.positions[i], 1.0f)); };
    for (size_t f = 0; f < mesh.triangle_count(); ++f)
      out.push_back({world(mesh.indices[3 * f]), world(mesh.indices[3 * f + 1]),
                     world(mesh.indices[3 * f + 2])});
  }
  return out;
}

// Incoherent rays, generated up front so generation is not timed. Surface origins model
// secondary rays of a path tracer: a point uniform over the scene's area, a direction
// uniform on the sphere, the origin pushed off the surface to the direction's side.
std::vector<Ray> generate_rays(const Scene& scene, size_t count, bool on_surface, uint64_t seed) {
  Rng rng(seed);
  std::vector<Ray> rays(count);
  const Bounds3 bounds = scene.bounds();
  std::vector<WorldTriangle> tris;
  std::vector<double> cdf;
  if (on_surface) {
    tris = world_triangles(scene);
    double total = 0.0;
    for (const WorldTriangle& t : tris) {
      total += 0.5 * glm::length(glm::cross(t.b - t.a, t.c - t.a));
      cdf.push_back(total);
    }
    if (!(total > 0.0)) on_surface = false;  // no area to start from: use the bounds
  }
  for (Ray& ray : rays) {
    ray.direction = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
    if (on_surface) {
      const double u = rng.next_float() * cdf.back();
      const size_t i = std::min<size_t>(
          static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()),
          tris.size() - 1);
      const WorldTriangle& t = tris[i];
      const vec2 b = sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
      const vec3 p = (1.0f - b.x - b.y) * t.a + b.x * t.b + b.y * t.c;
      const vec3 n = glm::cross(t.b - t.a, t.c - t.a);
      ray.origin = offset_ray_origin(p, glm::normalize(n), ray.direction);
    } else {
      const vec3 u(rng.next_float(), rng.next_float(), rng.next_float());
      ray.origin = bounds.min + u * bounds.extent();
    }
  }
  return rays;
}

template <typename Body>
double timed_parallel(size_t count, const Body& body) {
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(
      tbb::blocked_range<int64_t>(0, static_cast<int64_t>(count), kChunk),
      [&](const tbb::blocked_range<int64_t>& r) { body(r.begin(), r.end()); },
      tbb::simple_partitioner());
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

enum Method { kSingle, kBatch, kRaw, kMethodCount };
const char* const kMethodNames[kMethodCount] = {"illum_single", "illum_batch", "raw_embree"};

double run_method(Method method, const RayTracer& tracer, const std::vector<Ray>& rays,
                  std::vector<Hit>& hits) {
  switch (method) {
    case kSingle:
      return timed_parallel(rays.size(), [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) tracer.intersect(rays[i], &hits[i]);
      });
    case kBatch:
      return timed_parallel(rays.size(), [&](int64_t begin, int64_t end) {
        const size_t n = static_cast<size_t>(end - begin);
        tracer.intersect(std::span<const Ray>(rays).subspan(begin, n),
                         std::span<Hit>(hits).subspan(begin, n));
      });
    case kRaw: {
      // What an application calling Embree directly would write: fill RTCRayHit from its
      // own ray, trace, copy the answer out.
      const RTCScene scene = static_cast<RTCScene>(tracer.embree_scene());
      return timed_parallel(rays.size(), [&](int64_t begin, int64_t end) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int64_t i = begin; i < end; ++i) {
          const Ray& ray = rays[i];
          RTCRayHit rh;
          rh.ray.org_x = ray.origin.x;
          rh.ray.org_y = ray.origin.y;
          rh.ray.org_z = ray.origin.z;
          rh.ray.tnear = ray.tmin;
          rh.ray.dir_x = ray.direction.x;
          rh.ray.dir_y = ray.direction.y;
          rh.ray.dir_z = ray.direction.z;
          rh.ray.time = 0.0f;
          rh.ray.tfar = ray.tmax;
          rh.ray.mask = 0xffffffffu;
          rh.ray.id = 0;
          rh.ray.flags = 0;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(scene, &context, &rh);
          Hit& hit = hits[i];
          hit.t = rh.ray.tfar;
          hit.instance = rh.hit.geomID;
          hit.primitive = rh.hit.primID;
          hit.barycentric = vec2(rh.hit.u, rh.hit.v);
        }
      });
    }
    case kMethodCount:
      break;
  }
  return 0.0;
}

// Rays whose hits differ between two methods (hit or miss, instance, primitive); float t may
// differ in the last bits between Embree's single-ray and stream kernels, so it is not
// compared.
size_t mismatches(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i)
    n += a[i].valid() != b[i].valid() ||
         (a[i].valid() && (a[i].instance != b[i].instance || a[i].primitive != b[i].primitive));
  return n;
}

}  // namespace

int run_rays(SuiteArgs args) {
  CLI::App app("Closest-hit throughput of incoherent rays: illum single / batch vs raw Embree",
               "illum-bench rays");
  std::string scene_name, json_path, origins = "surface";
  size_t ray_count = size_t{1} << 20;
  double seconds = 5.0;
  int threads = 0;
  uint64_t seed = 1;
  app.add_option("scene", scene_name, "built-in scene name or scene file")->required();
  app.add_option("--rays", ray_count, "rays per pass")
      ->check(CLI::Range(size_t{1}, size_t{1} << 28));
  app.add_option("--seconds", seconds, "measuring time (all rounds, all methods)")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--threads", threads, "TBB threads (0 = all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--origins", origins, "ray origins: on the surfaces or in the bounds")
      ->check(CLI::IsMember({"surface", "bounds"}));
  app.add_option("--seed", seed, "ray generation seed");
  app.add_option("--json", json_path, "write the results here");
  if (!parse_args(app, args)) return 0;

  check_output_folder(json_path);  // fail before minutes of measuring, not after
  const ThreadLimit limit(threads);
  const int thread_count = threads > 0 ? threads : ThreadLimit::hardware_threads();

  LoadOptions load_options;
  load_options.load_textures = false;
  const Scene scene = load_scene(scene_name, load_options);
  const size_t triangles = scene.triangle_count();
  if (triangles == 0) throw Error(fmt::format("{}: the scene has no triangles", scene_name));

  const auto build_start = std::chrono::steady_clock::now();
  const RayTracer tracer(scene);
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  const std::vector<Ray> rays = generate_rays(scene, ray_count, origins == "surface", seed);

  // Warm-up: one pass of each (page faults, caches, TBB threads), also used to size the
  // number of rounds and to check that the three methods agree.
  std::vector<Hit> hits[kMethodCount];
  double warm_s = 0.0;
  for (int m = 0; m < kMethodCount; ++m) {
    hits[m].resize(rays.size());
    warm_s += run_method(static_cast<Method>(m), tracer, rays, hits[m]);
  }
  const size_t mismatch_single = mismatches(hits[kSingle], hits[kRaw]);
  const size_t mismatch_batch = mismatches(hits[kBatch], hits[kRaw]);
  size_t hit_count = 0;
  for (const Hit& h : hits[kRaw]) hit_count += h.valid();
  const int rounds = std::clamp(static_cast<int>(seconds / std::max(warm_s, 1e-9)), 3, 1000);

  std::vector<double> mrays[kMethodCount];
  for (int r = 0; r < rounds; ++r)
    for (int m = 0; m < kMethodCount; ++m) {
      const double s = run_method(static_cast<Method>(m), tracer, rays, hits[m]);
      mrays[m].push_back(static_cast<double>(rays.size()) / s * 1e-6);
    }

  double med[kMethodCount], lo[kMethodCount], hi[kMethodCount];
  for (int m = 0; m < kMethodCount; ++m) {
    med[m] = median(mrays[m]);
    lo[m] = *std::min_element(mrays[m].begin(), mrays[m].end());
    hi[m] = *std::max_element(mrays[m].begin(), mrays[m].end());
  }
  const double ratio_single = med[kSingle] / med[kRaw];
  const double ratio_batch = med[kBatch] / med[kRaw];
  // Paired ratios: each round's method against the raw loop of the same round, so slow
  // drifts of the machine's speed cancel; their median is the more robust estimate.
  double paired[kMethodCount];
  for (int m = 0; m < kMethodCount; ++m) {
    std::vector<double> r;
    for (int k = 0; k < rounds; ++k) r.push_back(mrays[m][k] / mrays[kRaw][k]);
    paired[m] = median(r);
  }
  const nlohmann::json machine = machine_info();

  std::printf(
      "rays: scene %s, %zu triangles (BVH build %.2f s), %zu rays from the %s, "
      "%.1f%% hit\n",
      scene.name.c_str(), triangles, build_s, rays.size(), origins.c_str(),
      100.0 * static_cast<double>(hit_count) / static_cast<double>(rays.size()));
  std::printf("      %d threads, %d interleaved rounds, %s\n", thread_count, rounds,
              machine["cpu"].get<std::string>().c_str());
  std::printf("  %-14s %12s %10s %10s %10s %10s\n", "method", "Mrays/s med", "min", "max",
              "ratio/raw", "paired");
  for (int m = 0; m < kMethodCount; ++m)
    std::printf("  %-14s %12.3f %10.3f %10.3f %10.3f %10.3f\n", kMethodNames[m], med[m], lo[m],
                hi[m], med[m] / med[kRaw], paired[m]);
  if (mismatch_single || mismatch_batch)
    std::printf("  warning: hits differ from raw Embree: single %zu, batch %zu rays\n",
                mismatch_single, mismatch_batch);

  if (!json_path.empty()) {
    nlohmann::json j;
    j["suite"] = "rays";
    j["scene"] = scene.name;
    j["scene_arg"] = scene_name;
    j["triangles"] = triangles;
    j["rays"] = rays.size();
    j["origins"] = origins;
    j["seed"] = seed;
    j["threads"] = thread_count;
    j["rounds"] = rounds;
    j["hit_fraction"] = static_cast<double>(hit_count) / static_cast<double>(rays.size());
    j["build_s"] = build_s;
    for (int m = 0; m < kMethodCount; ++m) {
      j["mrays_per_s"][kMethodNames[m]] = med[m];
      j["mrays_per_s_rounds"][kMethodNames[m]] = mrays[m];
    }
    j["ratio_single"] = ratio_single;
    j["ratio_batch"] = ratio_batch;
    j["ratio_single_paired"] = paired[kSingle];
    j["ratio_batch_paired"] = paired[kBatch];
    j["mismatched_hits"] = {{"illum_single", mismatch_single}, {"illum_batch", mismatch_batch}};
    j["machine"] = machine;
    write_json(json_path, j);
  }
  return 0;
}

}  // namespace illum::bench
