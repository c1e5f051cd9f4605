// Ambient occlusion: the cosine-weighted fraction of the hemisphere around the shading
// normal that is free of geometry within `distance`, output as grey 1 − occlusion.
#pragma once

#include <optional>

#include "illum/render/integrator.h"

namespace illum {

class AoIntegrator final : public Integrator {
 public:
  // Params: `samples` (AO rays per camera sample, default 4, 1..1024), `distance` (occluder
  // search distance in scene units, default 0.1 × the scene's bounding-box diagonal).
  explicit AoIntegrator(const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

  static constexpr float kDefaultDistanceFraction = 0.1f;

 private:
  int samples_ = 4;
  std::optional<float> distance_;
};

}  // namespace illum
