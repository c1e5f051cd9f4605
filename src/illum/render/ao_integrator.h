// Ambient occlusion: the cosine-weighted fraction of the hemisphere around the shading
// normal that is free of geometry within `distance`, output as grey 1 − occlusion.
//
// With `bias` b and `falloff` s the occlusion becomes the estimand of the real-time SSAO
// add-on (Méndez's term, S001 §4.3; docs/realtime.md "SSAO"):
//   A(x) = 1 − (1/π) ∫_Ω V_R(x, ω) · max(cos θ − b, 0) · g(t(ω)) dω,
//   g(t) = 1 / (1 + (t/s)²)  (s = 0: g = 1),
// where V_R is 1 when the ray hits geometry within R = `distance` at distance t(ω). b = 0,
// s = 0 is plain AO, the default.
#pragma once

#include <optional>

#include "illum/render/integrator.h"

namespace illum {

class AoIntegrator final : public Integrator {
 public:
  // Params: `samples` (AO rays per camera sample, default 4, 1..1024), `distance` (occluder
  // search distance in scene units, default 0.1 × the scene's bounding-box diagonal),
  // `bias` (subtracted from cos θ, default 0, [0, 1)), `falloff` (distance unit s of the
  // falloff 1/(1 + (t/s)²) in scene units, default 0 = no falloff).
  explicit AoIntegrator(const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

  static constexpr float kDefaultDistanceFraction = 0.1f;

  // The weight of one occluded cosine-distributed ray at cos θ = `cos_theta` (> 0) with its
  // hit at distance t: max(cos θ − b, 0) · g(t) / cos θ (the estimand's integrand over the
  // cosine pdf cos θ/π).
  static float occlusion_weight(float cos_theta, float t, float bias, float falloff);

 private:
  int samples_ = 4;
  std::optional<float> distance_;
  float bias_ = 0.0f;
  float falloff_ = 0.0f;
};

}  // namespace illum
