// Debug views from one closest-hit query per sample: `normals`, `albedo` and `depth`.
#pragma once

#include "illum/render/integrator.h"

namespace illum {

class DebugIntegrator final : public Integrator {
 public:
  enum class Mode {
    kNormals,  // world shading normal n mapped to colour 0.5·n + 0.5
    kAlbedo,   // reflectance the material shows at normal incidence, textures applied
    kDepth,    // hit distance t (grey): t / scene diagonal, or raw t with normalize=false
  };
  // Params: depth: `normalize` (bool, default true). Others take none.
  DebugIntegrator(Mode mode, const Params& params);
  Image render(const RayTracer& tracer, const Camera& camera,
               const RenderOptions& options) override;

 private:
  Mode mode_;
  bool normalize_depth_ = true;
};

}  // namespace illum
