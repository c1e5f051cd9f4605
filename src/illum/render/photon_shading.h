// Shading pieces shared by the photon-mapping and SPPM integrators: next-event estimation
// of direct light (one light chosen by power) and the BRDF weight of a gathered photon.
#pragma once

#include <optional>

#include "illum/core/sampler.h"
#include "illum/render/bsdf.h"
#include "illum/render/light_sampler.h"
#include "illum/render/material_eval.h"
#include "illum/render/photon_map.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

// Direct light reflected toward wo at si: f·L_i·|cos θ|/(pdf·pmf) for one light sample.
// `visibility` false skips the shadow ray (unshadowed estimate, S004's Whitted lights).
Color photon_direct_lighting(const RayTracer& tracer, const LightSampler& lights,
                             const SurfaceInteraction& si, const Bsdf& bsdf, const vec3& wo,
                             float u_light, const vec2& u, bool visibility = true);

// f_r for a photon gathered at si: zero for photons stored on a surface facing elsewhere
// (across a corner or on the other side of a thin wall), which the kd-tree cannot tell apart.
inline Color photon_brdf(const Bsdf& bsdf, const SurfaceInteraction& si, const vec3& wo,
                         const Photon& photon) {
  if (glm::dot(photon.normal, si.ng) < 0.7f) return Color(0.0f);
  return bsdf.eval(wo, photon.wi);
}

// Follows a camera ray through delta surfaces (mirror, glass, metal) to the first surface
// with a non-delta BSDF, adding the emission and environment seen on the way times the path
// throughput β. There it adds β · at_diffuse(si, bsdf, wo, β) and stops: photon density
// estimates take over from that vertex. Nothing is added when the path ends on a delta
// surface after max_depth bounces or is absorbed.
template <typename AtDiffuse>
Color trace_to_first_diffuse(const RayTracer& tracer, const LightSampler& lights, Ray ray,
                             int max_depth, SobolSampler& sampler, AtDiffuse&& at_diffuse) {
  const Scene& scene = tracer.scene();
  Color L(0.0f), beta(1.0f);
  for (int depth = 0; depth <= max_depth; ++depth) {
    Hit hit;
    if (!tracer.intersect(ray, &hit)) {
      // Seen directly or through delta surfaces only: nothing else accounts for it.
      if (lights.environment_light() >= 0) L += beta * lights.environment_radiance(ray.direction);
      break;
    }
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    L += beta * surface_emission(scene, si);
    const Bsdf bsdf(scene, si);
    const vec3 wo = -ray.direction;
    if (!bsdf.is_delta()) {
      L += beta * at_diffuse(si, bsdf, wo, beta);
      break;
    }
    const std::optional<BsdfSample> s = bsdf.sample(wo, sampler.next_1d(), sampler.next_2d());
    if (!s || is_black(s->weight)) break;
    beta *= s->weight;
    ray = Ray{offset_ray_origin(si.p, si.ng, s->wi), s->wi};
  }
  return L;
}

}  // namespace illum
