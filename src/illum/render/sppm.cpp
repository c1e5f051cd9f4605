#include "illum/render/sppm.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/core/progress.h"
#include "illum/core/sampler.h"
#include "illum/render/light_sampler.h"
#include "illum/render/material_eval.h"
#include "illum/render/photon_shading.h"
#include "illum/render/photon_tracer.h"
#include "illum/render/render_setup.h"

namespace illum {

namespace {

using glm::ivec3;

struct Pixel {
  Color direct{0.0f};  // Σ over iterations of emitted + direct light
  Color tau{0.0f};     // accumulated, radius-corrected flux
  float r2 = 0.0f;
  double n = 0.0;
  // This iteration's visible point.
  bool valid = false;
  vec3 p{0.0f}, wo{0.0f}, ng{0.0f};
  Color beta{0.0f};
  std::optional<Bsdf> bsdf;
  Color phi{0.0f};
  int m = 0;
};

struct Contribution {
  uint32_t pixel;
  Color phi;
};

// Hash grid over the visible points: each point is listed in every cell its radius
// touches; cells are cubes of side max radius (Hachisuka & Jensen 2009, pbrt's SPPM).
class VisiblePointGrid {
 public:
  explicit VisiblePointGrid(const std::vector<Pixel>& pixels) {
    float max_r2 = 0.0f;
    size_t count = 0;
    for (const Pixel& px : pixels) {
      if (!px.valid) continue;
      bounds_.extend(px.p);
      max_r2 = std::max(max_r2, px.r2);
      ++count;
    }
    if (count == 0 || !(max_r2 > 0.0f)) return;
    const float r = std::sqrt(max_r2);
    bounds_.min -= vec3(r);
    bounds_.max += vec3(r);
    cell_ = r;
    const vec3 e = bounds_.extent();
    for (int a = 0; a < 3; ++a)
      res_[a] = std::clamp(static_cast<int>(e[a] / cell_) + 1, 1, 1 << 20);
    table_ = count;
    std::vector<uint32_t> counts(table_ + 1, 0);
    // A point's cells may share hash buckets; list it once per bucket, or a photon in such
    // a bucket would be counted twice.
    std::vector<size_t> buckets;
    auto for_buckets = [&](const Pixel& px, auto&& fn) {
      const float pr = std::sqrt(px.r2);
      const ivec3 lo = cell_of(px.p - vec3(pr)), hi = cell_of(px.p + vec3(pr));
      buckets.clear();
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) buckets.push_back(hash(ivec3(x, y, z)));
      std::sort(buckets.begin(), buckets.end());
      buckets.erase(std::unique(buckets.begin(), buckets.end()), buckets.end());
      for (size_t h : buckets) fn(h);
    };
    for (const Pixel& px : pixels)
      if (px.valid) for_buckets(px, [&](size_t h) { ++counts[h + 1]; });
    for (size_t i = 1; i <= table_; ++i) counts[i] += counts[i - 1];
    offsets_ = counts;
    entries_.resize(counts[table_]);
    for (size_t i = 0; i < pixels.size(); ++i)
      if (pixels[i].valid)
        for_buckets(pixels[i], [&](size_t h) { entries_[counts[h]++] = static_cast<uint32_t>(i); });
  }

  template <typename Fn>
  void for_each_candidate(const vec3& p, Fn&& fn) const {
    if (table_ == 0) return;
    const vec3 q = (p - bounds_.min) / cell_;
    // Compare as floats first: photons far outside the grid would overflow an int.
    if (!(q.x >= 0.0f && q.y >= 0.0f && q.z >= 0.0f) || q.x >= static_cast<float>(res_[0]) ||
        q.y >= static_cast<float>(res_[1]) || q.z >= static_cast<float>(res_[2]))
      return;
    const ivec3 c(static_cast<int>(q.x), static_cast<int>(q.y), static_cast<int>(q.z));
    if (c.x >= res_[0] || c.y >= res_[1] || c.z >= res_[2]) return;
    const size_t h = hash(c);
    for (uint32_t i = offsets_[h]; i < offsets_[h + 1]; ++i) fn(entries_[i]);
  }

 private:
  ivec3 cell_of(const vec3& p) const {
    const vec3 q = (p - bounds_.min) / cell_;
    return glm::clamp(ivec3(static_cast<int>(std::floor(q.x)), static_cast<int>(std::floor(q.y)),
                            static_cast<int>(std::floor(q.z))),
                      ivec3(0), ivec3(res_[0] - 1, res_[1] - 1, res_[2] - 1));
  }
  size_t hash(const ivec3& c) const {
    const uint64_t h = (static_cast<uint64_t>(c.x) * 73856093u) ^
                       (static_cast<uint64_t>(c.y) * 19349663u) ^
                       (static_cast<uint64_t>(c.z) * 83492791u);
    return static_cast<size_t>(h % table_);
  }

  Bounds3 bounds_;
  float cell_ = 1.0f;
  int res_[3] = {1, 1, 1};
  size_t table_ = 0;
  std::vector<uint32_t> offsets_, entries_;
};

}  // namespace

SppmIntegrator::SppmIntegrator(const Params& params) {
  if (params.has("iterations")) {
    iterations_ = params.get<int>("iterations");
    if (iterations_ < 1)
      throw Error(fmt::format("sppm: iterations must be ≥ 1 (got {})", iterations_));
  }
  const int photons = params.get<int>("photons_per_iteration", 100000);
  if (photons < 1)
    throw Error(fmt::format("sppm: photons_per_iteration must be ≥ 1 (got {})", photons));
  photons_per_iteration_ = photons;
  if (params.has("initial_radius")) {
    initial_radius_ = params.get<float>("initial_radius");
    if (!(initial_radius_ > 0.0f))
      throw Error(fmt::format("sppm: initial_radius must be > 0 (got {})", initial_radius_));
  }
  alpha_ = params.get<float>("alpha", 0.7f);
  if (!(alpha_ > 0.0f && alpha_ < 1.0f))
    throw Error(fmt::format("sppm: alpha must lie in (0, 1) (got {})", alpha_));
  max_depth_ = params.get<int>("max_depth", -1);
  if (params.has("max_depth") && max_depth_ < 0)
    throw Error(fmt::format("sppm: max_depth must be ≥ 0 (got {})", max_depth_));
}

Image SppmIntegrator::render(const RayTracer& tracer, const Camera& camera,
                             const RenderOptions& options) {
  validate_render_options(options);
  ThreadLimit thread_limit(options.threads);
  const Scene& scene = tracer.scene();
  warn_about_scene(scene, true, "sppm");
  const LightSampler lights(scene);
  const int max_depth = max_depth_ >= 0 ? max_depth_ : scene.settings.max_bounces;
  const int iterations = iterations_ > 0 ? iterations_ : options.spp;
  const float r0 = initial_radius_ > 0.0f ? initial_radius_ : 0.01f * scene_scale(scene);
  const int width = options.width, height = options.height;
  std::vector<Pixel> pixels(static_cast<size_t>(width) * height);
  for (Pixel& px : pixels) px.r2 = r0 * r0;
  PhotonPathSettings path;
  path.max_depth = max_depth_ >= 0 ? max_depth_ : 16;

  Progress progress("sppm", iterations, options.progress);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  stats_ = Stats{};
  int done = 0;
  double iteration_end_s = 0.0;  // the budget check's clock reading, also the next start
  for (int it = 0; it < iterations; ++it) {
    stats_.last_iteration_start_s = iteration_end_s;
    // 1. Visible points.
    parallel_for_tiles(width, height, 16, [&](const Tile& tile) {
      for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
          Pixel& px = pixels[static_cast<size_t>(y) * width + x];
          px.valid = false;
          SobolSampler sampler(
              hash_mix(options.seed, static_cast<uint64_t>(x), static_cast<uint64_t>(y)));
          sampler.start_sample(static_cast<uint32_t>(it));
          const vec2 jitter = sampler.next_2d();
          Ray ray = camera.generate_ray(static_cast<float>(x) + jitter.x,
                                        static_cast<float>(y) + jitter.y, width, height);
          const Color L = trace_to_first_diffuse(tracer, lights, ray, max_depth, sampler,
                                                 [&](const SurfaceInteraction& si, const Bsdf& bsdf,
                                                     const vec3& wo, const Color& beta) {
                                                   const float u_light = sampler.next_1d();
                                                   const Color direct = photon_direct_lighting(
                                                       tracer, lights, si, bsdf, wo, u_light,
                                                       sampler.next_2d());
                                                   px.valid = true;
                                                   px.p = si.p;
                                                   px.wo = wo;
                                                   px.ng = si.ng;
                                                   px.beta = beta;
                                                   px.bsdf = bsdf;
                                                   return direct;
                                                 });
          if (is_finite(L)) px.direct += L;
        }
      }
    });

    // 2. Photons.
    const VisiblePointGrid grid(pixels);
    const std::vector<Contribution> contributions = trace_photons_parallel<Contribution>(
        lights, photons_per_iteration_, options.seed, 0x5B0000u + static_cast<uint64_t>(it),
        [&](int64_t, const LightEmission& e, Rng& rng, std::vector<Contribution>& sink) {
          trace_photon_path(
              tracer, e, rng, path,
              [&](const PhotonEvent& ev) {
                if (ev.depth == 0) return true;  // direct light: next-event estimation has it
                grid.for_each_candidate(ev.p, [&](uint32_t i) {
                  const Pixel& px = pixels[i];
                  const vec3 d = px.p - ev.p;
                  if (glm::dot(d, d) > px.r2 || glm::dot(px.ng, ev.ng) < 0.7f) return;
                  const Color f = px.bsdf->eval(px.wo, ev.wi);
                  if (!is_black(f)) sink.push_back({i, f * ev.power});
                });
                return true;
              },
              [](const PhotonEvent&) {});
        });
    for (const Contribution& c : contributions) {
      Pixel& px = pixels[c.pixel];
      px.phi += c.phi;
      ++px.m;
    }
    // 3. Radius and flux update.
    parallel_for(static_cast<int64_t>(pixels.size()), [&](int64_t b, int64_t e) {
      for (int64_t i = b; i < e; ++i) {
        Pixel& px = pixels[static_cast<size_t>(i)];
        if (px.m > 0) {
          const double n_new = px.n + alpha_ * px.m;
          const float ratio = static_cast<float>(n_new / (px.n + px.m));
          px.tau = (px.tau + px.beta * px.phi) * ratio;
          px.r2 *= ratio;
          px.n = n_new;
        }
        px.phi = Color(0.0f);
        px.m = 0;
      }
    });
    stats_.photons_emitted += photons_per_iteration_;
    ++done;
    progress.advance(1);
    if (interrupt_requested()) throw Interrupted{};
    iteration_end_s = elapsed();
    if (options.time_budget_s > 0.0 && iteration_end_s >= options.time_budget_s) break;
  }
  progress.finish();
  stats_.iterations = done;
  stats_.seconds = elapsed();

  Image image(width, height, 3);
  const double np = static_cast<double>(stats_.photons_emitted);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Pixel& px = pixels[static_cast<size_t>(y) * width + x];
      const Color indirect = px.tau / static_cast<float>(np * kPi * px.r2);
      image.set_rgb(x, y, px.direct / static_cast<float>(done) + indirect);
    }
  }
  return image;
}

}  // namespace illum
