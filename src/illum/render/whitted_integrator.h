// Whitted ray tracer (S004 post 1, ALGORITHMS.md A.1). Direct light from every light at
// diffuse and glossy surfaces, perfect mirror/conductor reflection and dielectric
// reflection + refraction (Fresnel + Snell, both branches traced) up to `max_depth`.
//
// Light model: the scene stores point/spot intensity I = Φ/(4π) resp. Φ/Ω, so the
// irradiance I·cosθ/r² is exactly S004's E = Φ·cosθ/(Ω·r²) with Ω = 2π(1 − cos θc), zero
// outside the cone (hard edge); point lights Φ·cosθ/(4π r²). Lambert reflects ρ/π·E.
//
// Extensions (not in S004, which has only point and spot lights):
// - area and environment lights light diffuse surfaces through `light_samples` shadowed
//   samples each per hit (0: they only show where seen directly or through specular
//   chains); emitters are visible to the camera and in mirrors; the environment is the
//   background.
// - `shadows=false` skips shadow rays, reproducing the seed's first image (its shadows
//   were meant to come from negative-flux photons later).
#pragma once

#include "illum/render/integrator.h"

namespace illum {

class WhittedIntegrator final : public Integrator {
 public:
  // Params: `max_depth` (specular recursion depth, default 5, 0..64), `shadows` (default
  // true), `light_samples` (area/environment light samples per hit, default 1, 0..256).
  explicit WhittedIntegrator(const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

 private:
  int max_depth_ = 5;
  bool shadows_ = true;
  int light_samples_ = 1;
};

}  // namespace illum
