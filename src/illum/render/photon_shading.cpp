#include "illum/render/photon_shading.h"

#include <cmath>

namespace illum {

Color photon_direct_lighting(const RayTracer& tracer, const LightSampler& lights,
                             const SurfaceInteraction& si, const Bsdf& bsdf, const vec3& wo,
                             float u_light, const vec2& u, bool visibility) {
  float pmf = 0.0f;
  const int light = lights.choose(u_light, &pmf);
  if (light < 0 || !(pmf > 0.0f)) return Color(0.0f);
  const std::optional<LightSample> ls = lights.sample_li(light, si.p, u);
  // A zero distance happens when p lies on the sampled emitter itself.
  if (!ls || !(ls->pdf > 0.0f) || is_black(ls->li) || !(ls->distance > 0.0f)) return Color(0.0f);
  const Color f = bsdf.eval(wo, ls->wi);
  if (is_black(f)) return Color(0.0f);
  if (visibility) {
    // The shared shadow ray aims at the sampled light point and stops just short of it.
    const Ray shadow = shadow_ray(si.p, si.ng, *ls);
    if (tracer.occluded(shadow)) return Color(0.0f);
  }
  const Color c = f * ls->li * (std::abs(glm::dot(ls->wi, si.ns)) / (ls->pdf * pmf));
  return is_finite(c) ? c : Color(0.0f);
}

}  // namespace illum
