// Photon mapping (Jensen 2001) with S004's density estimate L_r = (1/πr²)·Σ f_r·φ_p:
// camera rays follow delta surfaces; at the first non-delta surface the radiance is
//   emitted (seen directly or through delta surfaces)
//   + direct light by next-event estimation (or S004's unshadowed lights + shadow photons)
//   + caustics from the caustic map (L S+ D photons)
//   + indirect diffuse from the global map, either read directly at the hit point or by
//     final gathering: `gather_rays` BSDF-sampled rays whose first non-delta hit y returns
//     direct(y) + caustic(y) + global(y).
//
// Params (all optional):
//   photons          photons emitted for the global map       [200000, ≥ 1]
//   caustic_photons  photons emitted for the caustic map      [200000, ≥ 0]
//   k                neighbours per estimate (0: fixed radius) [100, ≥ 0]
//   radius           maximum (k > 0) or fixed (k = 0) gather radius, scene units
//                    [0.05 × the scene's bounding-box diagonal, > 0]
//   filter           none | cone | gaussian                   [cone]
//   cone_k           cone filter constant k ≥ 1                [1.1]
//   final_gather     true | false                             [true]
//   gather_rays      final-gather rays per camera sample      [4, ≥ 1]
//   precomputed_irradiance  true | false                      [true]
//                    final-gather rays ending on Lambertian surfaces read the global map's
//                    irradiance precomputed at every 4th photon (photon_irradiance.h)
//   shadow_photons   off | seed | skip                         [off]
//                    seed: S004 — direct light without shadow rays, shadows subtracted by
//                          the negative-flux shadow photons (biased like any estimate);
//                    skip: Jensen — a shadow ray only where the nearest shadow-map photons
//                          mix direct and shadow photons (single-light scenes; else as off)
//   max_depth        delta bounces followed from the camera / photon scatterings
//                    [the scene's max_bounces, photons 16]
#pragma once

#include <string>

#include "illum/render/integrator.h"
#include "illum/render/photon_map.h"

namespace illum {

class PhotonIntegrator final : public Integrator {
 public:
  explicit PhotonIntegrator(const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

  enum class ShadowMode { kOff, kSeed, kSkip };

 private:
  int64_t photons_ = 200000, caustic_photons_ = 200000;
  int k_ = 100;
  float radius_ = 0.0f;  // 0: default from the scene size
  FilterSettings filter_;
  bool final_gather_ = true;
  int gather_rays_ = 4;
  bool precomputed_irradiance_ = true;
  ShadowMode shadow_ = ShadowMode::kOff;
  int max_depth_ = -1;
  int photon_depth_ = 16;
};

}  // namespace illum
