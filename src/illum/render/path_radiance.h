// The path tracer's light transport, shared by the camera path tracer (path_integrator)
// and the light-map baker (bake/lightmap_baker): next-event estimation with MIS (power
// heuristic) at every non-delta vertex, BSDF sampling, Russian roulette and the bounce
// rules of path_integrator.h. Keeping one implementation means the baker cannot drift
// from the oracle it is checked against.
//
// Paths are numbered by vertex: the first surface a camera ray hits is vertex 0 (bounce 0);
// `max_bounces` is the last vertex whose emission still counts, so 0 shows only emitters.
// A caller that scatters at a vertex of its own (the baker's texel, vertex 0) continues the
// path with incident(ray, from) where `from` says how the ray was sampled, and adds the
// next-event estimate at its vertex with sample_direct(): together they estimate the light
// arriving there exactly as the path tracer does at one of its own vertices.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include "illum/core/color.h"
#include "illum/core/math.h"
#include "illum/core/sampler.h"
#include "illum/core/sampling.h"
#include "illum/render/light_sampler.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

struct PathRadianceOptions {
  int max_bounces = 8;  // last vertex number whose emission counts (see above)
  int rr_depth = 3;     // Russian roulette from vertex rr_depth − 1 on
  // Allowed counts of non-delta vertices between the light and the camera (bounce modes,
  // path_integrator.h); the defaults allow every path.
  int k_min = 0;
  int k_max = std::numeric_limits<int>::max();
};

// The vertex a ray leaves, as far as the estimate along the ray needs to know it.
struct PathVertex {
  vec3 p{0.0f};          // its position (the solid-angle pdf of area lights is taken from it)
  int bounce = 0;        // number of the vertex the ray will hit (0: a camera ray)
  int k = 0;             // non-delta vertices so far, this one included
  bool specular = true;  // camera or delta lobe: emitters the ray finds get full weight
  float pdf = 0.0f;      // solid-angle pdf the ray's direction was sampled with (MIS), if !specular
};

// One next-event estimation sample that reached a vertex unoccluded. Its contribution to a
// vertex with scattering factor s(wi) (BSDF × |cos|, or a light-map basis function) is
// s(wi) · li · mis_weight / pdf.
struct DirectLightSample {
  vec3 wi{0.0f};            // unit direction toward the light
  Color li{0.0f};           // LightSample::li: radiance, or irradiance for delta lights
  float pdf = 0.0f;         // selection pmf × solid-angle pdf (1 × pmf for delta lights)
  float mis_weight = 1.0f;  // power heuristic against the vertex's own sampling (1: delta)
  bool delta = false;
  int light = -1;
};

class PathRadiance {
 public:
  // `tracer` and `lights` must outlive this object; all queries are const and thread-safe.
  PathRadiance(const RayTracer& tracer, const LightSampler& lights,
               const PathRadianceOptions& options);

  // Radiance arriving at from.p along `ray` (which leaves `from`), estimated by tracing the
  // path on: emission found (MIS-weighted against next-event estimation at `from` when it
  // was not specular), next-event estimation and BSDF sampling at every further vertex.
  // `ray.origin` should already be offset off the surface. Adds the rays traced to *rays.
  Color incident(Ray ray, const PathVertex& from, SobolSampler& sampler, int64_t* rays) const;

  // The radiance a camera ray sees (from = the camera: vertex number 0, specular).
  Color camera(const Ray& ray, SobolSampler& sampler, int64_t* rays) const {
    return incident(ray, PathVertex{ray.origin, 0, 0, true, 0.0f}, sampler, rays);
  }

  // Next-event estimation at surface point p (unit geometric normal ng): picks a light with
  // u_light, samples a point of it with u_point and traces the shadow ray. Nothing when no
  // light is picked, the light cannot reach p, `skip_delta` is set and the light is a
  // delta light (point, spot, directional), `reflects(wi)` is false (the vertex scatters
  // nothing toward wi: the shadow ray is skipped), or the light is occluded.
  // `scatter_pdf(wi)` is the solid-angle pdf with which the vertex's own sampling picks wi,
  // for the MIS weight. Called as the path tracer calls it at each of its vertices.
  template <typename Reflects, typename ScatterPdf>
  std::optional<DirectLightSample> sample_direct(const vec3& p, const vec3& ng, float u_light,
                                                 const vec2& u_point, bool skip_delta,
                                                 Reflects&& reflects, ScatterPdf&& scatter_pdf,
                                                 int64_t* rays) const {
    if (lights_.light_count() <= 0) return std::nullopt;
    float pmf = 0.0f;
    const int light = lights_.choose(u_light, p, &pmf);
    if (light < 0 || !(pmf > 0.0f)) return std::nullopt;
    if (skip_delta && lights_.is_delta(light)) return std::nullopt;
    const std::optional<LightSample> ls = lights_.sample_li(light, p, u_point);
    if (!ls || !reflects(ls->wi)) return std::nullopt;
    const Ray shadow = shadow_ray(p, ng, *ls);
    ++*rays;
    if (tracer_.occluded(shadow)) return std::nullopt;
    DirectLightSample d;
    d.wi = ls->wi;
    d.li = ls->li;
    d.pdf = pmf * ls->pdf;
    d.mis_weight = ls->delta ? 1.0f : power_heuristic(d.pdf, scatter_pdf(ls->wi));
    d.delta = ls->delta;
    d.light = light;
    return d;
  }

  const LightSampler& lights() const { return lights_; }
  const PathRadianceOptions& options() const { return options_; }

 private:
  bool allowed(int k) const { return k >= options_.k_min && k <= options_.k_max; }

  const RayTracer& tracer_;
  const Scene& scene_;
  const LightSampler& lights_;
  PathRadianceOptions options_;
};

}  // namespace illum
