// Shading pieces shared by the photon-mapping and SPPM integrators: next-event estimation
// of direct light (one light chosen by power) and the BRDF weight of a gathered photon.
#pragma once

#include "illum/render/bsdf.h"
#include "illum/render/light_sampler.h"
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

}  // namespace illum
