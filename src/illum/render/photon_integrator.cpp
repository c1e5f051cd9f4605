#include "illum/render/photon_integrator.h"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/render/light_sampler.h"
#include "illum/render/material_eval.h"
#include "illum/render/photon_irradiance.h"
#include "illum/render/photon_shading.h"
#include "illum/render/photon_tracer.h"
#include "illum/render/tile_renderer.h"

namespace illum {

namespace {

// Every 4th global photon carries a precomputed irradiance (Christensen 1999 uses the same).
constexpr int kIrradianceStride = 4;

PhotonIntegrator::ShadowMode parse_shadow_mode(const std::string& s) {
  if (s == "off") return PhotonIntegrator::ShadowMode::kOff;
  if (s == "seed") return PhotonIntegrator::ShadowMode::kSeed;
  if (s == "skip") return PhotonIntegrator::ShadowMode::kSkip;
  throw Error(
      fmt::format("photon: shadow_photons '{}' is unknown (expected off, seed or skip)", s));
}

}  // namespace

PhotonIntegrator::PhotonIntegrator(const Params& params) {
  const int photons = params.get<int>("photons", 200000);
  if (photons < 1) throw Error(fmt::format("photon: photons must be ≥ 1 (got {})", photons));
  photons_ = photons;
  const int caustic = params.get<int>("caustic_photons", 200000);
  if (caustic < 0)
    throw Error(fmt::format("photon: caustic_photons must be ≥ 0 (got {})", caustic));
  caustic_photons_ = caustic;
  k_ = params.get<int>("k", 100);
  if (k_ < 0) throw Error(fmt::format("photon: k must be ≥ 0 (got {})", k_));
  if (params.has("radius")) {
    radius_ = params.get<float>("radius");
    if (!(radius_ > 0.0f)) throw Error(fmt::format("photon: radius must be > 0 (got {})", radius_));
  }
  filter_.type = parse_photon_filter(params.get<std::string>("filter", "cone"));
  filter_.cone_k = params.get<float>("cone_k", 1.1f);
  if (!(filter_.cone_k >= 1.0f))
    throw Error(fmt::format("photon: cone_k must be ≥ 1 (got {})", filter_.cone_k));
  final_gather_ = params.get<bool>("final_gather", true);
  gather_rays_ = params.get<int>("gather_rays", 4);
  if (gather_rays_ < 1)
    throw Error(fmt::format("photon: gather_rays must be ≥ 1 (got {})", gather_rays_));
  precomputed_irradiance_ = params.get<bool>("precomputed_irradiance", true);
  shadow_ = parse_shadow_mode(params.get<std::string>("shadow_photons", "off"));
  max_depth_ = params.get<int>("max_depth", -1);
  if (params.has("max_depth") && max_depth_ < 0)
    throw Error(fmt::format("photon: max_depth must be ≥ 0 (got {})", max_depth_));
  if (max_depth_ >= 0) photon_depth_ = max_depth_;
}

Image PhotonIntegrator::render(const RayTracer& tracer, const Camera& camera,
                               const RenderOptions& options) {
  validate_render_options(options);
  const Scene& scene = tracer.scene();
  warn_about_scene(scene, true, "photon");
  const LightSampler lights(scene);
  const int max_depth = max_depth_ >= 0 ? max_depth_ : scene.settings.max_bounces;
  const float radius = radius_ > 0.0f ? radius_ : 0.05f * scene_scale(scene);

  PhotonMapSettings ms;
  ms.global_photons = photons_;
  ms.caustic_photons = caustic_photons_;
  ms.path.max_depth = photon_depth_;
  ms.path.shadow_photons = shadow_ != ShadowMode::kOff;
  ms.seed = options.seed;
  PhotonMaps maps;
  {
    ThreadLimit limit(options.threads);
    maps = build_photon_maps(tracer, lights, ms);
  }
  log::info(
      "photon: {} global, {} caustic, {} shadow photons stored ({:.2f} s tracing, {:.2f} s "
      "building)",
      maps.global.size(), maps.caustic.size(), maps.shadow.size(), maps.trace_seconds,
      maps.build_seconds);
  PhotonMap irradiance;
  if (final_gather_ && precomputed_irradiance_) {
    const auto t0 = std::chrono::steady_clock::now();
    ThreadLimit limit(options.threads);
    irradiance = precompute_irradiance(maps.global, kIrradianceStride, k_, radius, filter_);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    maps.build_seconds += seconds;
    log::info("photon: irradiance precomputed at {} points ({:.2f} s)", irradiance.size(), seconds);
  }
  const bool skip_usable = shadow_ == ShadowMode::kSkip && lights.light_count() == 1;
  constexpr int kShadowK = 16;

  // Direct light at a non-delta point, by the chosen shadow mode.
  auto direct = [&](const SurfaceInteraction& si, const Bsdf& bsdf, const vec3& wo,
                    SobolSampler& sampler, std::vector<PhotonNeighbor>* scratch) -> Color {
    const float u_light = sampler.next_1d();
    const vec2 u = sampler.next_2d();
    if (shadow_ == ShadowMode::kSeed) {
      const Color unshadowed =
          photon_direct_lighting(tracer, lights, si, bsdf, wo, u_light, u, false);
      const Color shadow = estimate_radiance(
          maps.shadow, si.p, k_, radius, filter_,
          [&](const Photon& ph) {
            return ph.power.r < 0.0f || ph.power.g < 0.0f || ph.power.b < 0.0f
                       ? photon_brdf(bsdf, si, wo, ph)
                       : Color(0.0f);
          },
          scratch);
      return unshadowed + shadow;
    }
    if (skip_usable) {
      maps.shadow.knn(si.p, kShadowK, radius, scratch);
      int lit = 0, dark = 0;
      for (const PhotonNeighbor& nb : *scratch) {
        const Photon& ph = maps.shadow.photon(nb.index);
        if (glm::dot(ph.normal, si.ng) < 0.7f) continue;
        (ph.power.r + ph.power.g + ph.power.b > 0.0f ? lit : dark)++;
      }
      if (lit > 0 && dark == 0)
        return photon_direct_lighting(tracer, lights, si, bsdf, wo, u_light, u, false);
      if (dark > 0 && lit == 0) return Color(0.0f);
    }
    return photon_direct_lighting(tracer, lights, si, bsdf, wo, u_light, u, true);
  };
  auto caustics = [&](const SurfaceInteraction& si, const Bsdf& bsdf, const vec3& wo,
                      std::vector<PhotonNeighbor>* scratch) -> Color {
    if (maps.caustic.empty()) return Color(0.0f);
    return estimate_radiance(
        maps.caustic, si.p, k_, radius, filter_,
        [&](const Photon& ph) { return photon_brdf(bsdf, si, wo, ph); }, scratch);
  };
  auto global = [&](const SurfaceInteraction& si, const Bsdf& bsdf, const vec3& wo,
                    std::vector<PhotonNeighbor>* scratch) -> Color {
    if (maps.global.empty()) return Color(0.0f);
    return estimate_radiance(
        maps.global, si.p, k_, radius, filter_,
        [&](const Photon& ph) { return photon_brdf(bsdf, si, wo, ph); }, scratch);
  };

  // Indirect light at a gather hit: the precomputed irradiance for Lambertian surfaces.
  auto gathered_global = [&](const SurfaceInteraction& y, const Bsdf& by, const vec3& wy,
                             std::vector<PhotonNeighbor>* scratch) -> Color {
    if (!irradiance.empty() && by.type() == MaterialType::kLambert) {
      if (const std::optional<Color> e =
              lookup_irradiance(irradiance, y.p, y.ng, wy, radius, scratch)) {
        const vec3 side = glm::dot(wy, y.ng) > 0.0f ? y.ng : -y.ng;
        return by.eval(wy, side) * *e;
      }
    }
    return global(y, by, wy, scratch);
  };

  // Radiance leaving the first non-delta surface along a final-gather ray.
  auto gather = [&](const SurfaceInteraction& x, const Bsdf& bsdf, const vec3& wo,
                    SobolSampler& sampler, std::vector<PhotonNeighbor>* scratch) -> Color {
    Color sum(0.0f);
    for (int g = 0; g < gather_rays_; ++g) {
      const float u_lobe = sampler.next_1d();
      const vec2 u = sampler.next_2d();
      const std::optional<BsdfSample> s = bsdf.sample(wo, u_lobe, u);
      if (!s || is_black(s->weight)) continue;
      Color beta = s->weight;
      Ray ray{offset_ray_origin(x.p, x.ng, s->wi), s->wi};
      for (int depth = 0; depth <= max_depth; ++depth) {
        Hit hit;
        if (!tracer.intersect(ray, &hit)) break;  // light from the sky is direct: NEE has it
        const SurfaceInteraction y = tracer.interaction(ray, hit);
        const Bsdf by(scene, y);
        const vec3 wy = -ray.direction;
        if (!by.is_delta()) {
          sum += beta * (direct(y, by, wy, sampler, scratch) + caustics(y, by, wy, scratch) +
                         gathered_global(y, by, wy, scratch));
          break;
        }
        const std::optional<BsdfSample> sy = by.sample(wy, sampler.next_1d(), sampler.next_2d());
        if (!sy || is_black(sy->weight)) break;
        beta *= sy->weight;
        ray = Ray{offset_ray_origin(y.p, y.ng, sy->wi), sy->wi};
      }
    }
    return sum / static_cast<float>(gather_rays_);
  };

  // A time budget covers the whole render: what photon tracing used is gone.
  RenderOptions tile_options = options;
  if (options.time_budget_s > 0.0)
    tile_options.time_budget_s =
        std::max(1e-3, options.time_budget_s - maps.trace_seconds - maps.build_seconds);
  return render_tiles(
      camera, tile_options, "photon", [&](const Ray& camera_ray, SobolSampler& sampler) {
        thread_local std::vector<PhotonNeighbor> scratch;
        return trace_to_first_diffuse(
            tracer, lights, camera_ray, max_depth, sampler,
            [&](const SurfaceInteraction& si, const Bsdf& bsdf, const vec3& wo, const Color&) {
              // Named steps fix the order in which they draw sampler dimensions.
              const Color direct_and_caustics =
                  direct(si, bsdf, wo, sampler, &scratch) + caustics(si, bsdf, wo, &scratch);
              const Color indirect = final_gather_ ? gather(si, bsdf, wo, sampler, &scratch)
                                                   : global(si, bsdf, wo, &scratch);
              return direct_and_caustics + indirect;
            });
      });
}

}  // namespace illum
