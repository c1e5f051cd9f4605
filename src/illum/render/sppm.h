// Stochastic progressive photon mapping (Hachisuka & Jensen 2009). Each iteration:
//   1. camera pass: one jittered ray per pixel follows delta surfaces to its first
//      non-delta hit, the pixel's visible point (emission on the way and direct light there
//      by next-event estimation are accumulated directly);
//   2. photon pass: photons_per_iteration photons are traced; every non-delta hit after
//      the first (direct light is already counted) adds f·φ to the visible points within
//      their radius, found through a hash grid over the visible points;
//   3. per pixel with M new photons: N' = N + αM, r' = r·√(N'/(N+M)),
//      τ' = (τ + β·Σf·φ)·r'²/r².
// Radiance = direct/emitted mean + τ/(N_emitted·π·r²). Consistent: bias and variance both
// vanish as iterations grow (α ∈ (0,1)).
//
// Params: iterations (default: the render's spp), photons_per_iteration [100000, ≥ 1],
// initial_radius [0.01 × scene bounding-box diagonal, > 0], alpha [0.7, in (0,1)],
// max_depth [scene max_bounces for camera rays, 16 for photons].
// Determinism: photons use per-photon RNG streams and contributions are applied in photon
// order, so the image depends only on the seed (and on the time budget, if one is set).
#pragma once

#include "illum/render/integrator.h"

namespace illum {

class SppmIntegrator final : public Integrator {
 public:
  explicit SppmIntegrator(const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

  // Statistics of the last render (benchmarks and tests).
  struct Stats {
    int iterations = 0;
    int64_t photons_emitted = 0;
    double seconds = 0.0;
    // When the last iteration began: with a time budget the render stops after the first
    // iteration that ends past it, so this lies before the budget.
    double last_iteration_start_s = 0.0;
  };
  const Stats& stats() const { return stats_; }

 private:
  int iterations_ = -1;  // −1: options.spp
  int64_t photons_per_iteration_ = 100000;
  float initial_radius_ = 0.0f;  // 0: from the scene size
  float alpha_ = 0.7f;
  int max_depth_ = -1;
  Stats stats_;
};

}  // namespace illum
