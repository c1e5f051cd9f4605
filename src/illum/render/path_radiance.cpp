#include "illum/render/path_radiance.h"

#include <algorithm>
#include <cmath>

#include "illum/render/bsdf.h"
#include "illum/render/material_eval.h"

namespace illum {

PathRadiance::PathRadiance(const RayTracer& tracer, const LightSampler& lights,
                           const PathRadianceOptions& options)
    : tracer_(tracer), scene_(tracer.scene()), lights_(lights), options_(options) {}

Color PathRadiance::incident(Ray ray, const PathVertex& from, SobolSampler& sampler,
                             int64_t* rays) const {
  Color l(0.0f), beta(1.0f);
  int k = from.k;                 // non-delta vertices so far
  bool specular = from.specular;  // previous vertex was the camera or a delta lobe
  float prev_pdf = from.pdf;      // sampling pdf of the direction that led here
  vec3 prev_p = from.p;
  for (int bounce = from.bounce;; ++bounce) {
    Hit hit;
    ++*rays;
    if (!tracer_.intersect(ray, &hit)) {
      const int env = lights_.environment_light();
      if (env >= 0 && allowed(k)) {
        const Color le = lights_.environment_radiance(ray.direction);
        float w = 1.0f;
        if (!specular)
          w = power_heuristic(prev_pdf,
                              lights_.pmf(env, prev_p) * lights_.pdf_environment(ray.direction));
        l += beta * le * w;
      }
      break;
    }
    const SurfaceInteraction si = tracer_.interaction(ray, hit);
    if (allowed(k)) {
      const Color le = surface_emission(scene_, si);
      if (!is_black(le)) {
        float w = 1.0f;
        if (!specular && si.light >= 0)
          w = power_heuristic(
              prev_pdf, lights_.pmf(si.light, prev_p) * lights_.pdf_li_area(si.light, prev_p, si));
        l += beta * le * w;
      }
    }
    if (bounce >= options_.max_bounces) break;
    const Bsdf bsdf(scene_, si);
    const bool delta = bsdf.is_delta();
    const int k_next = delta ? k : k + 1;
    // Nothing further along this path can be counted.
    if (k_next > options_.k_max) break;

    // Every vertex takes the same five sampler pairs (light choice, light point, lobe,
    // direction, roulette) whether it uses them or not, so that the dimensions line up
    // between neighbouring samples; the ones it does not use are skipped, not computed
    // (the image is the same bytes either way).
    if (!delta && allowed(k_next)) {
      const float u_light = sampler.next_1d();
      const vec2 u_point = sampler.next_2d();
      Color f(0.0f);
      const std::optional<DirectLightSample> d = sample_direct(
          si.p, si.ng, u_light, u_point, /*skip_delta=*/false,
          [&](const vec3& wi) {
            f = bsdf.eval(si.wo, wi);
            return !is_black(f);
          },
          [&](const vec3& wi) { return bsdf.pdf(si.wo, wi); }, rays);
      if (d) {
        const float cos_theta = std::abs(glm::dot(d->wi, si.ns));
        l += beta * f * d->li * (cos_theta * d->mis_weight / d->pdf);
      }
    } else {
      sampler.skip();
      sampler.skip();
    }

    float u_lobe = 0.0f;
    if (bsdf.uses_lobe_choice())
      u_lobe = sampler.next_1d();
    else
      sampler.skip();
    const vec2 u_dir = sampler.next_2d();
    const std::optional<BsdfSample> bs = bsdf.sample(si.wo, u_lobe, u_dir);
    if (!bs || is_black(bs->weight)) break;
    beta *= bs->weight;
    specular = bs->delta;
    prev_pdf = bs->pdf;
    prev_p = si.p;
    k = k_next;
    if (bounce + 1 < options_.rr_depth) {
      sampler.skip();
    } else {
      const float u_rr = sampler.next_1d();
      // Continue with probability √(max β) rather than max β (Cycles' rule): β falls by the
      // albedo at every bounce, so max β ended most paths of a dim interior after three
      // bounces while their indirect light is much of the image. Measured with
      // `illum-bench converge` (src/illum/render/README.md, "Speed"): variance per sample
      // −16 to −23 % on Cornell and Sibenik, the time per sample within the run-to-run
      // spread (±10 %). Unbiased either way.
      const float q = std::max(0.05f, 1.0f - std::min(1.0f, std::sqrt(max_component(beta))));
      if (u_rr < q) break;
      beta /= 1.0f - q;
    }
    ray = Ray{offset_ray_origin(si.p, si.ng, bs->wi), bs->wi};
  }
  return l;
}

}  // namespace illum
