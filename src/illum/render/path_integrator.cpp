#include "illum/render/path_integrator.h"

#include <limits>

#include "illum/core/error.h"
#include "illum/core/sampling.h"
#include "illum/render/bsdf.h"
#include "illum/render/light_sampler.h"
#include "illum/render/material_eval.h"

namespace illum {

namespace {

struct PathTracer {
  const RayTracer& tracer;
  const Scene& scene;
  const LightSampler& lights;
  int max_bounces;
  int k_min, k_max;  // allowed counts of non-delta vertices (see path_integrator.h)
  int rr_depth;

  bool allowed(int k) const { return k >= k_min && k <= k_max; }

  Color li(Ray ray, SobolSampler& sampler, int64_t* rays) const {
    Color l(0.0f), beta(1.0f);
    int k = 0;              // non-delta vertices so far
    bool specular = true;   // previous vertex was the camera or a delta lobe
    float prev_pdf = 0.0f;  // BSDF pdf of the direction that led here
    vec3 prev_p = ray.origin;
    for (int bounce = 0;; ++bounce) {
      Hit hit;
      ++*rays;
      if (!tracer.intersect(ray, &hit)) {
        const int env = lights.environment_light();
        if (env >= 0 && allowed(k)) {
          const Color le = lights.environment_radiance(ray.direction);
          float w = 1.0f;
          if (!specular)
            w = power_heuristic(prev_pdf, lights.pmf(env) * lights.pdf_environment(ray.direction));
          l += beta * le * w;
        }
        break;
      }
      const SurfaceInteraction si = tracer.interaction(ray, hit);
      if (allowed(k)) {
        const Color le = surface_emission(scene, si);
        if (!is_black(le)) {
          float w = 1.0f;
          if (!specular && si.light >= 0)
            w = power_heuristic(prev_pdf,
                                lights.pmf(si.light) * lights.pdf_li_area(si.light, prev_p, si));
          l += beta * le * w;
        }
      }
      if (bounce >= max_bounces) break;
      const Bsdf bsdf(scene, si);
      const bool delta = bsdf.is_delta();
      const int k_next = delta ? k : k + 1;
      // Nothing further along this path can be counted.
      if (k_next > k_max) break;

      // Light sampling dimensions are drawn even when unused so that the sampler's
      // dimensions line up between neighbouring samples.
      const float u_light = sampler.next_1d();
      const vec2 u_point = sampler.next_2d();
      if (!delta && allowed(k_next) && lights.light_count() > 0) {
        float pmf = 0.0f;
        const int light = lights.choose(u_light, &pmf);
        if (light >= 0 && pmf > 0.0f) {
          if (const std::optional<LightSample> ls = lights.sample_li(light, si.p, u_point)) {
            const Color f = bsdf.eval(si.wo, ls->wi);
            if (!is_black(f)) {
              const Ray shadow = shadow_ray(si.p, si.ng, *ls);
              ++*rays;
              if (!tracer.occluded(shadow)) {
                const float cos_theta = std::abs(glm::dot(ls->wi, si.ns));
                const float light_pdf = pmf * ls->pdf;
                const float w =
                    ls->delta ? 1.0f : power_heuristic(light_pdf, bsdf.pdf(si.wo, ls->wi));
                l += beta * f * ls->li * (cos_theta * w / light_pdf);
              }
            }
          }
        }
      }

      const float u_lobe = sampler.next_1d();
      const vec2 u_dir = sampler.next_2d();
      const std::optional<BsdfSample> bs = bsdf.sample(si.wo, u_lobe, u_dir);
      if (!bs || is_black(bs->weight)) break;
      beta *= bs->weight;
      specular = bs->delta;
      prev_pdf = bs->pdf;
      prev_p = si.p;
      k = k_next;
      const float u_rr = sampler.next_1d();
      if (bounce + 1 >= rr_depth) {
        const float q = std::max(0.05f, 1.0f - std::min(1.0f, max_component(beta)));
        if (u_rr < q) break;
        beta /= 1.0f - q;
      }
      ray = Ray{offset_ray_origin(si.p, si.ng, bs->wi), bs->wi};
    }
    return l;
  }
};

}  // namespace

PathIntegrator::PathIntegrator(const Params& params) {
  max_bounces_ = params.get_int_in("max_bounces", 8, 0, 1024);
  rr_depth_ = params.get_int_in("rr_depth", 3, 1, 1024);
  const std::string mode = params.get<std::string>("bounces", "all");
  if (mode == "all") {
    bounces_ = Bounces::kAll;
  } else if (mode == "direct") {
    bounces_ = Bounces::kDirect;
  } else if (mode == "indirect1") {
    bounces_ = Bounces::kIndirect1;
  } else {
    throw Error(fmt::format("{}: bounces must be all, direct or indirect1, not '{}'",
                            params.where("bounces"), mode));
  }
}

Image PathIntegrator::render(const RayTracer& tracer, const Camera& camera,
                             const RenderOptions& options) {
  warn_about_scene(tracer.scene(), true, "path");
  const LightSampler lights(tracer.scene());
  PathTracer pt{tracer,   tracer.scene(), lights, max_bounces_, 0, std::numeric_limits<int>::max(),
                rr_depth_};
  if (bounces_ == Bounces::kDirect) pt.k_max = 1;
  if (bounces_ == Bounces::kIndirect1) pt.k_min = pt.k_max = 2;
  std::atomic<int64_t> rays{0};
  stats_ = {};
  Image image = render_tiles(
      camera, options, "path",
      [&](const Ray& ray, SobolSampler& sampler) {
        int64_t n = 0;
        const Color c = pt.li(ray, sampler, &n);
        rays.fetch_add(n, std::memory_order_relaxed);
        return c;
      },
      &stats_.render);
  stats_.rays = rays.load();
  return image;
}

}  // namespace illum
