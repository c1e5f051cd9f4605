#include "illum/render/ao_integrator.h"

#include "illum/core/sampling.h"
#include "illum/render/tile_renderer.h"

namespace illum {

AoIntegrator::AoIntegrator(const Params& params) {
  samples_ = params.get_int_in("samples", 4, 1, 1024);
  if (params.has("distance"))
    distance_ = params.get_float_in("distance", 1.0f, 1e-9f, std::numeric_limits<float>::max());
  // b ≥ 1 would occlude nothing at all: a mistake rather than a setting.
  bias_ = params.get_float_in("bias", 0.0f, 0.0f, std::nextafter(1.0f, 0.0f));
  falloff_ = params.get_float_in("falloff", 0.0f, 0.0f, std::numeric_limits<float>::max());
}

float AoIntegrator::occlusion_weight(float cos_theta, float t, float bias, float falloff) {
  float w = std::max(cos_theta - bias, 0.0f) / cos_theta;
  if (falloff > 0.0f) {
    const float d = t / falloff;
    w /= 1.0f + d * d;
  }
  return w;
}

Image AoIntegrator::render(const RayTracer& tracer, const Camera& camera,
                           const RenderOptions& options) {
  const Scene& scene = tracer.scene();
  warn_about_scene(scene, false, "ao");
  const float distance = distance_.value_or(kDefaultDistanceFraction * scene_scale(scene));
  const float inv_samples = 1.0f / static_cast<float>(samples_);
  // Plain AO counts open rays (exactly today's images); the weighted estimand needs the hit
  // distance and the cosine.
  const bool weighted = bias_ > 0.0f || falloff_ > 0.0f;
  // Camera misses are black ("no surface"), like the other debug views.
  return render_tiles(camera, options, "ao", [&](const Ray& ray, SobolSampler& sampler) -> Color {
    Hit hit;
    if (!tracer.intersect(ray, &hit)) return Color(0.0f);
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    // Two-sided: the hemisphere on the side the camera sees.
    const bool front = glm::dot(si.wo, si.ng) >= 0.0f;
    const vec3 ng = front ? si.ng : -si.ng;
    vec3 ns = front ? si.ns : -si.ns;
    if (glm::dot(ns, ng) <= 0.0f) ns = ng;
    const Frame frame = Frame::from_normal(ns);
    int open = 0;
    float occlusion = 0.0f;
    for (int i = 0; i < samples_; ++i) {
      const vec3 local = sample_cosine_hemisphere(sampler.next_2d());
      const vec3 dir = frame.to_world(local);
      if (!weighted) {
        if (glm::dot(dir, ng) <= 0.0f) continue;  // below the geometric surface: occluded by it
        Ray shadow{offset_ray_origin(si.p, ng, dir), dir, 0.0f, distance};
        if (!tracer.occluded(shadow)) ++open;
        continue;
      }
      if (local.z <= 0.0f) continue;  // measure zero under the cosine pdf
      float t = 0.0f;                 // below the geometric surface: occluded at once
      if (glm::dot(dir, ng) > 0.0f) {
        Ray shadow{offset_ray_origin(si.p, ng, dir), dir, 0.0f, distance};
        Hit h;
        if (!tracer.intersect(shadow, &h)) continue;
        t = h.t;
      }
      occlusion += occlusion_weight(local.z, t, bias_, falloff_);
    }
    if (!weighted) return Color(static_cast<float>(open) * inv_samples);
    return Color(1.0f - occlusion * inv_samples);
  });
}

}  // namespace illum
