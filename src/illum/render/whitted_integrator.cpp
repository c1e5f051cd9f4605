#include "illum/render/whitted_integrator.h"

#include "illum/render/bsdf.h"
#include "illum/render/light_sampler.h"
#include "illum/render/material_eval.h"
#include "illum/render/tile_renderer.h"

namespace illum {

namespace {

class WhittedTracer {
 public:
  WhittedTracer(const RayTracer& tracer, const LightSampler& lights, int max_depth, bool shadows,
                int light_samples)
      : tracer_(tracer),
        scene_(tracer.scene()),
        lights_(lights),
        max_depth_(max_depth),
        shadows_(shadows),
        light_samples_(light_samples) {}

  Color radiance(const Ray& ray, int depth, SobolSampler& sampler) const {
    Hit hit;
    if (!tracer_.intersect(ray, &hit)) return lights_.environment_radiance(ray.direction);
    const SurfaceInteraction si = tracer_.interaction(ray, hit);
    Color l = surface_emission(scene_, si);
    const Bsdf bsdf(scene_, si);
    if (!bsdf.is_delta()) return l + direct(si, bsdf, sampler);
    if (depth >= max_depth_) return l;
    // Specular: trace every lobe (dielectrics: reflection and refraction), each weighted
    // by its probability × its weight, i.e. F and (1 − F)·T/η².
    for (const float u_lobe : {0.0f, 0.99999994f}) {
      const std::optional<BsdfSample> s = bsdf.sample(si.wo, u_lobe, vec2(0.5f));
      if (!s || !(s->pdf > 0.0f)) continue;
      // First pass reflection, second refraction: under total internal reflection (or an
      // index of 1) both would pick the same lobe, which must count once.
      if ((u_lobe > 0.0f) != s->transmission) continue;
      Ray next{offset_ray_origin(si.p, si.ng, s->wi), s->wi};
      l += s->pdf * s->weight * radiance(next, depth + 1, sampler);
      if (bsdf.type() != MaterialType::kDielectric) break;  // mirror/conductor: one lobe
    }
    return l;
  }

 private:
  Color direct(const SurfaceInteraction& si, const Bsdf& bsdf, SobolSampler& sampler) const {
    Color l(0.0f);
    for (int i = 0; i < lights_.light_count(); ++i) {
      const bool delta = lights_.is_delta(i);
      const int n = delta ? 1 : light_samples_;
      for (int k = 0; k < n; ++k) {
        const vec2 u = delta ? vec2(0.5f) : sampler.next_2d();
        const std::optional<LightSample> ls = lights_.sample_li(i, si.p, u);
        if (!ls) continue;
        const Color f = bsdf.eval(si.wo, ls->wi);
        if (is_black(f)) continue;
        const float cos_theta = std::abs(glm::dot(ls->wi, si.ns));
        if (shadows_) {
          const Ray shadow = shadow_ray(si.p, si.ng, *ls);
          if (tracer_.occluded(shadow)) continue;
        }
        l += f * ls->li * (cos_theta / (ls->pdf * static_cast<float>(n)));
      }
    }
    return l;
  }

  const RayTracer& tracer_;
  const Scene& scene_;
  const LightSampler& lights_;
  int max_depth_;
  bool shadows_;
  int light_samples_;
};

}  // namespace

WhittedIntegrator::WhittedIntegrator(const Params& params) {
  max_depth_ = params.get_int_in("max_depth", 5, 0, 64);
  shadows_ = params.get<bool>("shadows", true);
  light_samples_ = params.get_int_in("light_samples", 1, 0, 256);
}

Image WhittedIntegrator::render(const RayTracer& tracer, const Camera& camera,
                                const RenderOptions& options) {
  warn_about_scene(tracer.scene(), true, "whitted");
  const LightSampler lights(tracer.scene());
  const WhittedTracer whitted(tracer, lights, max_depth_, shadows_, light_samples_);
  return render_tiles(camera, options, "whitted", [&](const Ray& ray, SobolSampler& sampler) {
    return whitted.radiance(ray, 0, sampler);
  });
}

}  // namespace illum
