#include "illum/bake/lightmap_baker.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "illum/bake/lightmap_denoiser.h"
#include "illum/bake/lightmap_seams.h"
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

constexpr int kMaxLayers = 4;
constexpr int kMaxSpp = 1 << 20;
constexpr int kMaxBounces = 1024;
constexpr int kMaxDilate = 64;
constexpr int kMaxBatches = 4;
constexpr float kMinDenoiseStrength = 0.1f;
constexpr float kMaxDenoiseStrength = 100.0f;
// Russian roulette starts where the path tracer's does (its default rr_depth), counting
// the texel as the path's first vertex.
constexpr int kRrDepth = 3;

// The texel's surface point as the first vertex of the paths: a Lambertian vertex whose
// "BSDF × cosine" is the basis function of each layer. Directions are sampled by cosine
// for the plain basis (its basis function is cos/π itself: every sample then weighs 1),
// and for the directional bases by an equal mixture of cosine and uniform hemisphere
// sampling: their basis functions do not vanish at the horizon (Y00, Y1±1, the tilted
// RNM lobes), where a cosine pdf alone would give them infinite variance; the uniform half
// bounds every weight by 4π·max|basis|. The pdf of the mixture is what MIS sees, exactly
// as the path tracer's Phong vertex uses its lobe mixture's pdf.
struct TexelVertex {
  vec3 p, ng, n;
  Frame sampling;  // right-handed frame around n for the warps
  vec3 t, b;       // the TexelSample tangent frame: b = cross(n, t) · tangent_sign
  LightmapBasis basis = LightmapBasis::kPlain;

  explicit TexelVertex(const atlas::TexelSample& s, LightmapBasis lightmap_basis)
      : p(s.position),
        ng(s.geometric_normal),
        n(s.normal),
        sampling(Frame::from_normal(s.normal)),
        t(s.tangent),
        b(glm::cross(s.normal, s.tangent) * s.tangent_sign),
        basis(lightmap_basis) {}

  bool mixture() const { return basis != LightmapBasis::kPlain; }
  // Above the texel's hemisphere and not below its geometric surface (as Bsdf: no leaks).
  bool valid(const vec3& w) const { return glm::dot(w, n) > 0.0f && glm::dot(w, ng) > 0.0f; }
  float density(float cos_theta) const {
    const float cosine = cos_theta * kInvPi;
    return mixture() ? 0.5f * cosine + 0.5f * pdf_uniform_hemisphere() : cosine;
  }
  float pdf(const vec3& w) const { return valid(w) ? density(glm::dot(w, n)) : 0.0f; }
  vec3 sample(float u_lobe, const vec2& u) const {
    const vec3 local =
        !mixture() || u_lobe < 0.5f ? sample_cosine_hemisphere(u) : sample_uniform_hemisphere(u);
    return glm::normalize(sampling.to_world(local));
  }
  // Basis function of each layer for a valid direction w.
  void weights(const vec3& w, float* out) const { basis_weights(basis, w, n, t, b, out); }
};

// Weights of each layer's luminance in the denoiser's guide: a quantity that every layer's
// noise shows up in. RNM: the mean of the three lobes (together they cover the hemisphere,
// about the irradiance); SH: the band-0 coefficient (the mean radiance), since the band-1
// ones change sign with the light's direction.
std::vector<float> guide_weights(LightmapBasis basis) {
  switch (basis) {
    case LightmapBasis::kPlain:
      return {1.0f};
    case LightmapBasis::kRnm:
      return {1.0f / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f};
    case LightmapBasis::kShL1:
      return {1.0f, 0.0f, 0.0f, 0.0f};
    case LightmapBasis::kDominant:
      // Of the SH sums it is made from: E/π on the normal, c2/(π·Y1 factor), which the
      // dominant layers reproduce there exactly (lightmap_basis.h).
      return {0.0f, 0.0f, static_cast<float>(1.0 / (kPi * sh::kY1)), 0.0f};
  }
  throw Error(fmt::format("light-map bake: unknown basis {}", static_cast<int>(basis)));
}

// The variance of a texel's estimate, for the denoiser, from the spread of the means of
// `batches` runs of consecutive samples. Consecutive power-of-two runs of the shuffled,
// scrambled Sobol' sequence are nets in every dimension pair, so a run's mean already has
// the stratification's benefit (a 1-D choice such as sun or sky comes out balanced in every
// run of two), which the textbook s²/n — each sample counted as independent — misses: at 8
// spp it let a sun shadow's step leak 28% onto the texels beside the edge, against 7% with
// runs (bake/README.md). 4 runs (3 degrees of freedom) once there are 8 samples, so every
// run holds two or more; 2 below (1 degree: rough, which the denoiser's 3×3 prefilter of
// the variance evens out).
int variance_batches(int spp) {
  return spp >= 8 ? 4 : spp >= 2 ? 2 : 1;
}

// Var(mean) ≈ K/(K−1)·Σ_b (n_b/n)²(m_b − m)² for K runs of n_b samples with sums `sums`
// (the textbook estimate when every run holds one sample). One sample says nothing about
// its spread: the squared mean then stands for it (a relative error of 100%, as one path
// often has).
double batch_variance(const double* sums, int batches, int spp) {
  double total = 0.0;
  for (int b = 0; b < batches; ++b) total += sums[b];
  const double mean = total / spp;
  if (batches < 2) return mean * mean;
  double spread = 0.0;
  for (int b = 0; b < batches; ++b) {
    // Sample k belongs to run ⌊k·K/spp⌋: run b holds k ∈ [⌈b·spp/K⌉, ⌈(b+1)·spp/K⌉).
    const int64_t first = (int64_t(b) * spp + batches - 1) / batches;
    const int64_t end = (int64_t(b + 1) * spp + batches - 1) / batches;
    const double n = static_cast<double>(end - first);
    const double d = sums[b] / n - mean;
    spread += n * n * d * d;
  }
  return spread / (double(spp) * spp) * batches / (batches - 1);
}

void validate(const LightmapBakeOptions& o) {
  if (o.basis != LightmapBasis::kPlain && o.basis != LightmapBasis::kRnm &&
      o.basis != LightmapBasis::kShL1 && o.basis != LightmapBasis::kDominant)
    throw Error(fmt::format("light-map bake: unknown basis {}", static_cast<int>(o.basis)));
  if (o.content != LightmapContent::kAll && o.content != LightmapContent::kIndirect)
    throw Error(fmt::format("light-map bake: unknown content {}", static_cast<int>(o.content)));
  if (o.spp < 1 || o.spp > kMaxSpp)
    throw Error(fmt::format("light-map bake: spp = {} must lie in [1, {}]", o.spp, kMaxSpp));
  if (o.max_bounces < 0 || o.max_bounces > kMaxBounces)
    throw Error(fmt::format("light-map bake: max_bounces = {} must lie in [0, {}]", o.max_bounces,
                            kMaxBounces));
  if (o.dilate < 0 || o.dilate > kMaxDilate)
    throw Error(
        fmt::format("light-map bake: dilate = {} must lie in [0, {}]", o.dilate, kMaxDilate));
  if (o.threads < 0)
    throw Error(fmt::format("light-map bake: threads = {} must be ≥ 0", o.threads));
  if (!(o.time_budget_s >= 0.0) || !std::isfinite(o.time_budget_s))
    throw Error(fmt::format("light-map bake: time budget {} s must be ≥ 0", o.time_budget_s));
  if (o.time_budget_s > 0.0 && (o.spp & (o.spp - 1)) != 0)
    throw Error(fmt::format(
        "light-map bake: spp = {} with a time budget must be a power of two (the bake stops "
        "between passes that double the samples per texel)",
        o.spp));
  if (o.time_budget_s > 0.0 && work_split_ranks() > 1)
    throw Error("light-map bake: a time budget cannot be split across MPI ranks");
  if (!(o.denoise_strength >= kMinDenoiseStrength && o.denoise_strength <= kMaxDenoiseStrength))
    throw Error(fmt::format("light-map bake: denoise_strength = {} must lie in [{}, {}]",
                            o.denoise_strength, kMinDenoiseStrength, kMaxDenoiseStrength));
}

void validate(const Scene& scene, const RayTracer& tracer, const atlas::TexelRaster& raster) {
  if (&tracer.scene() != &scene)
    throw Error("light-map bake: the ray tracer was built from another scene");
  atlas::check_texel_raster(scene, raster, "light-map bake");
}

// A texel's running sums: the layers' and, per variance run, the guide luminance's.
struct TexelSums {
  glm::dvec3 sum[kMaxLayers];
  double batch_sum[kMaxBatches];
};

// One texel's result: what the root needs to fill the maps, and the counts.
struct TexelRecord {
  Color layer[kMaxLayers];
  float variance;
  int64_t rays;
  int64_t dropped;
};

// The estimate of every texel's layers: paths from the texel's surface point (TexelVertex),
// one scrambled Sobol' sequence per texel.
struct TexelEstimator {
  const atlas::TexelRaster& raster;
  const PathRadiance& transport;
  LightmapBasis basis;  // the accumulated one (SH-L1 for dominant)
  int layers;
  const std::vector<float>& guide;
  uint64_t seed;
  // kIndirect leaves the direct light of delta lights to the real-time renderer; rays never
  // hit a delta light, so skipping them in next-event estimation at the texel removes
  // exactly that and nothing else.
  bool skip_delta;

  // Adds samples [first, end) of texel i's sequence to `sums`; the runs are those of a bake
  // of `end` samples (sample k in run ⌊k·K/end⌋). Stops early only on Ctrl-C.
  void add_samples(int64_t i, int first, int end, TexelSums& sums, int64_t* rays,
                   int64_t* dropped_samples) const {
    const atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
    const TexelVertex v(s, basis);
    const int batches = variance_batches(end);
    // One scrambled Sobol' sequence per texel, seeded like a pixel's: the texel's value
    // depends only on (seed, x, y, spp), never on scheduling or on the passes.
    SobolSampler sampler(hash_mix(seed, static_cast<uint64_t>(s.x), static_cast<uint64_t>(s.y)));
    float w[kMaxLayers] = {};
    for (int k = first; k < end; ++k) {
      // Texels of a million samples take seconds: poll Ctrl-C inside them too.
      if ((k & 1023) == 1023 && interrupt_requested()) break;
      sampler.start_sample(static_cast<uint32_t>(k));
      Color estimate[kMaxLayers] = {};
      // The dimensions are drawn in the path tracer's order at a vertex: light
      // choice, light point, lobe, direction, roulette.
      const float u_light = sampler.next_1d();
      const vec2 u_point = sampler.next_2d();
      const std::optional<DirectLightSample> d = transport.sample_direct(
          v.p, v.ng, u_light, u_point, skip_delta, [&](const vec3& wi) { return v.valid(wi); },
          [&](const vec3& wi) { return v.pdf(wi); }, rays);
      if (d) {
        v.weights(d->wi, w);
        const float scale = d->mis_weight / d->pdf;
        for (int j = 0; j < layers; ++j) estimate[j] += d->li * (w[j] * scale);
      }
      const float u_lobe = sampler.next_1d();
      const vec2 u_dir = sampler.next_2d();
      (void)sampler.next_1d();  // the roulette dimension (no roulette at the texel)
      const vec3 wi = v.sample(u_lobe, u_dir);
      const float pdf = v.pdf(wi);
      if (pdf > 0.0f) {
        const Ray ray{offset_ray_origin(v.p, v.ng, wi), wi};
        const Color li = transport.incident(ray, PathVertex{v.p, 1, 1, false, pdf}, sampler, rays);
        v.weights(wi, w);
        for (int j = 0; j < layers; ++j) estimate[j] += li * (w[j] / pdf);
      }
      bool finite = true;
      for (int j = 0; j < layers; ++j) finite = finite && is_finite(estimate[j]);
      if (!finite) {
        ++*dropped_samples;
        continue;
      }
      double g = 0.0;
      for (int j = 0; j < layers; ++j) {
        sums.sum[j] += glm::dvec3(estimate[j]);
        g += double(guide[static_cast<size_t>(j)]) * double(luminance(estimate[j]));
      }
      sums.batch_sum[static_cast<int64_t>(k) * batches / end] += g;
    }
  }

  void finish(const TexelSums& sums, int spp, TexelRecord& record) const {
    const double inv_spp = 1.0 / static_cast<double>(spp);
    for (int j = 0; j < layers; ++j) record.layer[j] = Color(sums.sum[j] * inv_spp);
    record.variance =
        static_cast<float>(batch_variance(sums.batch_sum, variance_batches(spp), spp));
  }

  void store(int64_t i, const TexelRecord& record, LightmapBake* bake) const {
    const atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
    for (int j = 0; j < layers; ++j)
      bake->layers[static_cast<size_t>(j)].set_rgb(s.x, s.y, record.layer[j]);
    bake->variance.pixel(s.x, s.y)[0] = record.variance;
  }
};

// Every texel at options.spp samples. Texels are independent (one sampler each), so they are
// split across MPI ranks when the run has several (core/work_split.h) with the same values as
// in one process; the denoiser and dilation afterwards read neighbours and run after every
// texel is in.
void bake_planned(const TexelEstimator& estimator, int spp, Progress& progress,
                  std::atomic<int64_t>& total_rays, std::atomic<int64_t>& dropped,
                  LightmapBake* bake) {
  split_items<TexelRecord>(
      static_cast<int64_t>(estimator.raster.samples.size()), 16,
      [&](int64_t i) {
        TexelRecord record{};
        if (interrupt_requested()) return record;  // Ctrl-C: finish quickly, throw below
        TexelSums sums{};
        estimator.add_samples(i, 0, spp, sums, &record.rays, &record.dropped);
        estimator.finish(sums, spp, record);
        return record;
      },
      [&](int64_t i, const TexelRecord& record) {
        estimator.store(i, record, bake);
        total_rays += record.rays;
        if (record.dropped) dropped += record.dropped;
        progress.advance(1);
      });
  bake->spp = spp;
}

// At N → 2N samples the old variance runs (sample ranges aligned to powers of two) merge into
// the new ones that contain them.
void merge_variance_runs(int done, int end, std::vector<TexelSums>& sums) {
  const int old_batches = variance_batches(done), new_batches = variance_batches(end);
  for (TexelSums& t : sums) {
    double merged[kMaxBatches] = {};
    for (int b = 0; b < old_batches; ++b) {
      const int64_t first = (int64_t(b) * done + old_batches - 1) / old_batches;
      merged[first * new_batches / end] += t.batch_sum[b];
    }
    std::copy(merged, merged + kMaxBatches, t.batch_sum);
  }
}

// Passes to 1, 2, 4, … samples per texel until options.spp or until the next pass is
// predicted to end past the time budget. Every texel keeps its sums between passes and
// continues its own sequence, so a texel's sums after the pass to N are exactly those of a
// bake at spp = N; a power-of-two prefix of the Sobol' sequence is a complete net, so the
// estimate where the bake stops keeps the stratification of a planned one.
void bake_timed(const TexelEstimator& estimator, const LightmapBakeOptions& options,
                std::chrono::steady_clock::time_point start, Progress& progress,
                std::atomic<int64_t>& total_rays, std::atomic<int64_t>& dropped,
                LightmapBake* bake) {
  const int64_t count = static_cast<int64_t>(estimator.raster.samples.size());
  std::vector<TexelSums> sums(static_cast<size_t>(count), TexelSums{});
  bake->passes = 0;
  int done = 0;
  double last_pass_s = 0.0;
  int last_pass_samples = 0;
  while (done < options.spp) {
    const int end = done == 0 ? 1 : 2 * done;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (done > 0 && elapsed + last_pass_s * double(end - done) / double(last_pass_samples) >
                        options.time_budget_s) {
      bake->stopped_by_time = true;
      break;
    }
    if (done > 0) merge_variance_runs(done, end, sums);
    const auto pass_start = std::chrono::steady_clock::now();
    parallel_for(
        count,
        [&](int64_t begin, int64_t stop) {
          int64_t rays = 0, dropped_samples = 0;
          for (int64_t i = begin; i < stop && !interrupt_requested(); ++i) {
            estimator.add_samples(i, done, end, sums[static_cast<size_t>(i)], &rays,
                                  &dropped_samples);
            progress.advance(end - done);
          }
          total_rays += rays;
          dropped += dropped_samples;
        },
        16);
    if (interrupt_requested()) break;
    last_pass_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
    last_pass_samples = end - done;
    done = end;
    ++bake->passes;
  }
  bake->spp = done;
  if (!interrupt_requested())
    parallel_for(
        count,
        [&](int64_t begin, int64_t stop) {
          for (int64_t i = begin; i < stop; ++i) {
            TexelRecord record{};
            estimator.finish(sums[static_cast<size_t>(i)], done, record);
            estimator.store(i, record, bake);
          }
        },
        256);
  if (bake->stopped_by_time)
    log::info("bake: stopped by the {:.3g}s budget after {} of {} samples per texel",
              options.time_budget_s, done, options.spp);
}

// After the texels: denoise (if asked), dilate, stitch the seams (if asked), and turn SH-L1
// sums into dominant-direction maps.
void finish_layers(const Scene& scene, const atlas::TexelRaster& raster,
                   const LightmapBakeOptions& options, const std::vector<float>& guide,
                   LightmapBake* bake) {
  if (options.denoise) {
    const auto denoise_start = std::chrono::steady_clock::now();
    LightmapDenoiseOptions denoise_options;
    denoise_options.luminance_sigma = options.denoise_strength;
    denoise_lightmap(scene, raster, bake->layers, bake->variance, guide, denoise_options);
    bake->denoised = true;
    bake->denoise_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - denoise_start).count();
    log::info("bake: denoised {} texels in {:.2f}s", raster.samples.size(), bake->denoise_seconds);
  }
  for (Image& layer : bake->layers) atlas::dilate(layer, raster, options.dilate);
  if (options.stitch) {
    const StitchReport stitched =
        stitch_baked_layers(scene, raster, bake->layers, options.stitch_coplanar);
    bake->stitch_seconds = stitched.seconds;
    bake->seam_edges = stitched.seam_edges;
    bake->coplanar_edges = stitched.coplanar_edges;
    log::info(
        "bake: stitched {} seam edges and {} coplanar edge pairs ({} samples, {} texels, {} CG "
        "iterations) in {:.2f}s",
        stitched.seam_edges, stitched.coplanar_edges, stitched.solve.samples, stitched.solve.texels,
        stitched.solve.iterations, stitched.seconds);
  }
  if (options.basis == LightmapBasis::kDominant) bake->layers = dominant_from_sh(bake->layers);
}

}  // namespace

LightmapBakeOptions LightmapBakeOptions::from_params(const Params& params) {
  LightmapBakeOptions o;
  const auto named = [&](const char* key, auto parse, const char* fallback) {
    const std::string name = params.get<std::string>(key, fallback);
    try {
      return parse(name);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", params.where(key), e.what()));
    }
  };
  o.basis = named("basis", lightmap_basis_from_string, "plain");
  o.content = named("content", lightmap_content_from_string, "all");
  o.spp = params.get_int_in("spp", o.spp, 1, kMaxSpp);
  o.max_bounces = params.get_int_in("max_bounces", o.max_bounces, 0, kMaxBounces);
  o.dilate = params.get_int_in("dilate", o.dilate, 0, kMaxDilate);
  // The struct keeps the raw estimate for library callers; people baking through a file or
  // the CLI want the noise gone (see the header).
  o.denoise = params.get<bool>("denoise", true);
  o.denoise_strength = params.get_float_in("denoise_strength", o.denoise_strength,
                                           kMinDenoiseStrength, kMaxDenoiseStrength);
  o.stitch = params.get<bool>("stitch", true);
  o.stitch_coplanar = params.get<bool>("stitch_coplanar", o.stitch_coplanar);
  o.seed = params.get_seed("seed", o.seed);
  return o;
}

LightmapBake bake_lightmap(const Scene& scene, const RayTracer& tracer,
                           const atlas::TexelRaster& raster, const LightmapBakeOptions& options) {
  validate(options);
  validate(scene, tracer, raster);
  ThreadLimit thread_limit(options.threads);
  const auto start = std::chrono::steady_clock::now();

  // Dominant-direction maps are made from SH-L1 sums at the end (lightmap_basis.h).
  const LightmapBasis accumulated_basis = accumulation_basis(options.basis);
  const int layers = layer_count(accumulated_basis);
  LightmapBake bake;
  bake.basis = options.basis;
  bake.content = options.content;
  for (int i = 0; i < layers; ++i) bake.layers.emplace_back(raster.width, raster.height, 3);
  bake.variance = Image(raster.width, raster.height, 1);
  const std::vector<float> guide = guide_weights(options.basis);

  const LightSampler lights(scene);
  PathRadianceOptions transport_options;
  // The texel is vertex 0 of every path, so the light that reached it after max_bounces
  // scatterings was emitted by vertex max_bounces + 1.
  transport_options.max_bounces = options.max_bounces + 1;
  transport_options.rr_depth = kRrDepth;
  const PathRadiance transport(tracer, lights, transport_options);
  const TexelEstimator estimator{raster,
                                 transport,
                                 accumulated_basis,
                                 layers,
                                 guide,
                                 options.seed,
                                 options.content == LightmapContent::kIndirect};

  const int64_t count = static_cast<int64_t>(raster.samples.size());
  const bool timed = options.time_budget_s > 0.0;
  Progress progress("bake", timed ? count * int64_t(options.spp) : count, options.progress);
  std::atomic<int64_t> total_rays{0}, dropped{0};
  if (!timed)
    bake_planned(estimator, options.spp, progress, total_rays, dropped, &bake);
  else
    bake_timed(estimator, options, start, progress, total_rays, dropped, &bake);
  if (interrupt_requested()) {
    progress.finish();
    throw Interrupted{};
  }
  progress.finish();
  // Across ranks only the root received the texels; the others' maps are empty.
  if (const WorkSplit* split = work_split(); split && !split->is_root()) return bake;
  if (dropped.load() > 0)
    log::warn("bake: {} non-finite samples were replaced by black", dropped.load());
  finish_layers(scene, raster, options, guide, &bake);
  bake.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bake.rays = total_rays.load();
  bake.texels = raster.samples.size();
  return bake;
}

}  // namespace illum::bake
