// Offline renderers. Each integrator is created by name from parameters (explicit list in
// integrator.cpp) and renders a linear HDR image of a scene from a camera.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "illum/core/image.h"
#include "illum/core/params.h"
#include "illum/scene/scene.h"
#include "illum/trace/ray_tracer.h"

namespace illum {

struct RenderOptions {
  int width = 512;
  int height = 512;
  int spp = 16;                // samples per pixel (progressive integrators: the budget)
  uint64_t seed = 0;           // same seed + same thread count → same image
  int threads = 0;             // 0 = all cores
  double time_budget_s = 0.0;  // > 0: stop after this long (progressive integrators)
  bool progress = true;        // show a progress bar when stderr is a terminal
};

// Largest accepted image side; larger requests are refused (memory and time guard).
inline constexpr int kMaxImageSide = 16384;

class Integrator {
 public:
  virtual ~Integrator() = default;
  // `params` holds integrator-specific options; unread keys are an error after creation.
  static std::unique_ptr<Integrator> create(const std::string& name, const Params& params);
  static std::vector<std::string> names();

  virtual Image render(const RayTracer& tracer, const Camera& camera,
                       const RenderOptions& options) = 0;
};

}  // namespace illum
