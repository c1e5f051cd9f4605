#include "illum/bake/probe_baker.h"

#include <atomic>
#include <cfloat>
#include <chrono>
#include <cmath>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/core/progress.h"
#include "illum/core/rng.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"
#include "illum/core/sh.h"
#include "illum/core/work_split.h"
#include "illum/render/light_sampler.h"
#include "illum/render/path_radiance.h"

namespace illum::bake {

namespace {

constexpr int kMaxBounces = 1024;
// Λ_l of the clamped cosine for l = 0, 1, 2 (core/sh.h clamped_cosine_factors).
constexpr float kLambda[kProbeBands] = {float(kPi), float(2.0 * kPi / 3.0), float(kPi / 4.0)};
constexpr int kBand[kProbeCoefficients] = {0, 1, 1, 1, 2, 2, 2, 2, 2};
const vec3 kFaces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

void validate(const ProbeBakeOptions& o) {
  if (!(o.spacing >= 0.0f) || !std::isfinite(o.spacing))
    throw Error(
        fmt::format("probe bake: spacing = {} must be a finite number > 0 (or 0: the "
                    "default)",
                    o.spacing));
  if (o.spp < 1 || o.spp > kMaxProbeSpp)
    throw Error(fmt::format("probe bake: spp = {} must lie in [1, {}]", o.spp, kMaxProbeSpp));
  if (o.max_bounces < 0 || o.max_bounces > kMaxBounces)
    throw Error(fmt::format("probe bake: max_bounces = {} must lie in [0, {}]", o.max_bounces,
                            kMaxBounces));
  if (!(o.backface_threshold >= 0.0f && o.backface_threshold <= 1.0f))
    throw Error(fmt::format("probe bake: backface_threshold = {} must lie in [0, 1]",
                            o.backface_threshold));
  if (o.threads < 0) throw Error(fmt::format("probe bake: threads = {} must be ≥ 0", o.threads));
}

// World-space geometric normal of a hit's triangle (the winding's, as SurfaceInteraction::ng,
// without the texture work interaction() does).
vec3 hit_normal(const Scene& scene, const Hit& hit) {
  const Instance& inst = scene.instances[hit.instance];
  const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
  const uint32_t* t = &mesh.indices[size_t(hit.primitive) * 3];
  const vec3 a = vec3(inst.transform * vec4(mesh.positions[t[0]], 1.0f));
  const vec3 b = vec3(inst.transform * vec4(mesh.positions[t[1]], 1.0f));
  const vec3 c = vec3(inst.transform * vec4(mesh.positions[t[2]], 1.0f));
  return glm::cross(b - a, c - a);
}

struct ProbeResult {
  ProbeRecord record;
  float standard_error[kProbeCoefficients * 3];
  int64_t rays;
  int64_t dropped;
};

}  // namespace

ProbeGrid make_probe_grid(const Bounds3& bounds, float spacing) {
  if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max))
    throw Error("probe grid: the scene has no finite bounds (no geometry?)");
  const vec3 extent = bounds.max - bounds.min;
  if (spacing == 0.0f)
    spacing = std::max(max_component(extent), 1e-6f) / float(kDefaultProbesAlongLongestSide);
  if (!(spacing > 0.0f) || !std::isfinite(spacing))
    throw Error(fmt::format("probe grid: spacing = {} must be a finite number > 0", spacing));
  double n[3], probes = 1.0;
  for (int a = 0; a < 3; ++a) {
    n[a] = std::max(1.0, std::round(double(extent[a]) / double(spacing)));
    probes *= n[a];
  }
  const double bytes = probes * double(sizeof(ProbeRecord));
  if (bytes > kMaxProbeBytes)
    throw Error(fmt::format(
        "probe grid: spacing {} m over {:.4g}×{:.4g}×{:.4g} m gives {:.0f}×{:.0f}×{:.0f} = {:.4g} "
        "probes, {:.4g} bytes, more than the {:.0f} MiB limit; use a larger spacing",
        spacing, extent.x, extent.y, extent.z, n[0], n[1], n[2], probes, bytes,
        kMaxProbeBytes / double(1 << 20)));
  ProbeGrid grid;
  grid.size = glm::ivec3(int(n[0]), int(n[1]), int(n[2]));
  grid.spacing = spacing;
  grid.origin = bounds.center() - 0.5f * spacing * vec3(grid.size - 1);
  return grid;
}

ProbeBakeOptions ProbeBakeOptions::from_params(const Params& params) {
  ProbeBakeOptions o;
  o.spacing = params.get_float_in("spacing", o.spacing, 0.0f, FLT_MAX);
  o.spp = params.get_int_in("spp", o.spp, 1, kMaxProbeSpp);
  o.max_bounces = params.get_int_in("max_bounces", o.max_bounces, 0, kMaxBounces);
  o.backface_threshold =
      params.get_float_in("backface_threshold", o.backface_threshold, 0.0f, 1.0f);
  o.seed = params.get_seed("seed", o.seed);
  return o;
}

Color irradiance_from_sh(const float* e, const vec3& n) {
  float y[kProbeCoefficients];
  sh::evaluate<float>(kProbeBands, n, std::span<float>(y, kProbeCoefficients));
  Color c(0.0f);
  for (int i = 0; i < kProbeCoefficients; ++i)
    c += y[i] * Color(e[3 * i], e[3 * i + 1], e[3 * i + 2]);
  return c;
}

void ambient_cube_from_sh(const float* irradiance, float* cube) {
  for (int f = 0; f < 6; ++f) {
    const Color e = glm::max(irradiance_from_sh(irradiance, kFaces[f]), Color(0.0f)) * kInvPi;
    for (int c = 0; c < 3; ++c) cube[3 * f + c] = e[c];
  }
}

Color evaluate_ambient_cube(const float* cube, const vec3& n) {
  const vec3 n2 = n * n;
  const int fx = n.x >= 0.0f ? 0 : 1, fy = n.y >= 0.0f ? 2 : 3, fz = n.z >= 0.0f ? 4 : 5;
  auto face = [&](int f) { return Color(cube[3 * f], cube[3 * f + 1], cube[3 * f + 2]); };
  return n2.x * face(fx) + n2.y * face(fy) + n2.z * face(fz);
}

Color ambient_cube_error_bound(const float* e) {
  // E(n) in monomials from the closed forms (core/sh.h): band 1 = kY1·(y, z, x), band 2:
  // Y_2^−2 = kY2xy·xy, Y_2^−1 = kY2xy·yz, Y_2^1 = kY2xy·xz; Y_2^0 and Y_2^2 are diagonal.
  Color bound(0.0f);
  for (int c = 0; c < 3; ++c) {
    auto coef = [&](int i) { return double(e[3 * i + c]); };
    const double b = sh::kY1 * (std::abs(coef(1)) + std::abs(coef(2)) + std::abs(coef(3)));
    const double q = 0.5 * sh::kY2xy * (std::abs(coef(4)) + std::abs(coef(5)) + std::abs(coef(7)));
    bound[c] = float(b / 4.0 + q);
  }
  return bound;
}

std::vector<ProbeRecord> bake_probes_at(const Scene& scene, const RayTracer& tracer,
                                        const std::vector<vec3>& points,
                                        const ProbeBakeOptions& options,
                                        std::vector<float>* standard_errors,
                                        ProbeBakeStats* stats) {
  validate(options);
  if (&tracer.scene() != &scene)
    throw Error("probe bake: the ray tracer was built from another scene");
  for (const vec3& p : points)
    if (!is_finite(p)) throw Error("probe bake: a probe position is not finite");
  ThreadLimit thread_limit(options.threads);
  const auto start = std::chrono::steady_clock::now();
  const LightSampler lights(scene);
  PathRadianceOptions transport_options;
  transport_options.max_bounces = options.max_bounces;
  const PathRadiance transport(tracer, lights, transport_options);
  const float sphere_pdf = pdf_uniform_sphere();

  const int64_t count = int64_t(points.size());
  std::vector<ProbeRecord> records(points.size());
  if (standard_errors) standard_errors->assign(points.size() * kProbeCoefficients * 3, 0.0f);
  Progress progress("probes", count, options.progress);
  std::atomic<int64_t> total_rays{0}, dropped{0}, invalid{0};
  const double n = double(options.spp);

  // Probes are independent (one sampler each): split across MPI ranks like texels.
  split_items<ProbeResult>(
      count, 1,
      [&](int64_t index) {
        ProbeResult result{};
        if (interrupt_requested()) return result;
        const vec3 p = points[size_t(index)];
        SobolSampler sampler(hash_mix(options.seed, uint64_t(index), 0x70726f6265ULL));
        double sum[kProbeCoefficients][3] = {}, sum2[kProbeCoefficients][3] = {};
        int64_t backfaces = 0;
        float y[kProbeCoefficients];
        for (int k = 0; k < options.spp; ++k) {
          if ((k & 1023) == 1023 && interrupt_requested()) break;
          sampler.start_sample(uint32_t(k));
          Color estimate[kProbeCoefficients] = {};
          // The path tracer's order at a vertex: light choice, light point, lobe, direction,
          // roulette. The probe is a point in space: no surface to offset from (ng = 0).
          const float u_light = sampler.next_1d();
          const vec2 u_point = sampler.next_2d();
          const std::optional<DirectLightSample> d = transport.sample_direct(
              p, vec3(0.0f), u_light, u_point, /*skip_delta=*/false,
              [](const vec3&) { return true; }, [&](const vec3&) { return sphere_pdf; },
              &result.rays);
          if (d) {
            sh::evaluate<float>(kProbeBands, d->wi, std::span<float>(y, kProbeCoefficients));
            const Color li = d->li * (d->mis_weight / d->pdf);
            for (int i = 0; i < kProbeCoefficients; ++i) estimate[i] += y[i] * li;
          }
          (void)sampler.next_1d();  // the lobe dimension (one lobe: the sphere)
          const vec3 w = sample_uniform_sphere(sampler.next_2d());
          (void)sampler.next_1d();  // the roulette dimension (no roulette at the probe)
          const Ray ray{p, w};
          Hit hit;
          ++result.rays;
          if (tracer.intersect(ray, &hit) && glm::dot(hit_normal(scene, hit), w) > 0.0f)
            ++backfaces;
          const Color li = transport.incident(ray, PathVertex{p, 0, 0, false, sphere_pdf}, sampler,
                                              &result.rays) /
                           sphere_pdf;
          sh::evaluate<float>(kProbeBands, w, std::span<float>(y, kProbeCoefficients));
          for (int i = 0; i < kProbeCoefficients; ++i) estimate[i] += y[i] * li;
          bool finite = true;
          for (const Color& e : estimate) finite = finite && is_finite(e);
          if (!finite) {
            ++result.dropped;
            continue;
          }
          for (int i = 0; i < kProbeCoefficients; ++i)
            for (int c = 0; c < 3; ++c) {
              sum[i][c] += double(estimate[i][c]);
              sum2[i][c] += double(estimate[i][c]) * double(estimate[i][c]);
            }
        }
        ProbeRecord& r = result.record;
        for (int i = 0; i < kProbeCoefficients; ++i)
          for (int c = 0; c < 3; ++c) {
            const double mean = sum[i][c] / n;
            const double lambda = kLambda[kBand[i]];
            r.irradiance[3 * i + c] = float(lambda * mean);
            // s²/n of independent samples: an upper estimate for the scrambled Sobol' mean.
            const double var =
                n > 1 ? std::max(0.0, (sum2[i][c] / n - mean * mean) * n / (n - 1)) : mean * mean;
            result.standard_error[3 * i + c] = float(lambda * std::sqrt(var / n));
          }
        ambient_cube_from_sh(r.irradiance, r.cube);
        r.backface_fraction = float(double(backfaces) / n);
        r.weight = r.backface_fraction > options.backface_threshold ? 0.0f : 1.0f;
        return result;
      },
      [&](int64_t index, const ProbeResult& result) {
        records[size_t(index)] = result.record;
        if (standard_errors)
          std::copy(std::begin(result.standard_error), std::end(result.standard_error),
                    standard_errors->begin() + index * kProbeCoefficients * 3);
        total_rays += result.rays;
        if (result.dropped) dropped += result.dropped;
        if (result.record.weight == 0.0f) ++invalid;
        progress.advance(1);
      });
  progress.finish();
  if (interrupt_requested()) throw Interrupted{};
  if (dropped.load() > 0)
    log::warn("probe bake: {} non-finite samples were replaced by black", dropped.load());
  if (stats) {
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->rays = total_rays.load();
    stats->invalid = invalid.load();
  }
  return records;
}

ProbeBake bake_probes(const Scene& scene, const RayTracer& tracer,
                      const ProbeBakeOptions& options) {
  validate(options);
  if (scene.lights.empty())
    throw Error(fmt::format(
        "probe bake: scene '{}' has no light (no light, emissive surface or environment): every "
        "probe would be black",
        scene.name));
  ProbeBake bake;
  bake.grid = make_probe_grid(tracer.bounds(), options.spacing);
  std::vector<vec3> points(size_t(bake.grid.count()));
  for (int64_t i = 0; i < bake.grid.count(); ++i) points[size_t(i)] = bake.grid.position(i);
  bake.probes = bake_probes_at(scene, tracer, points, options, nullptr, &bake.stats);
  return bake;
}

}  // namespace illum::bake
