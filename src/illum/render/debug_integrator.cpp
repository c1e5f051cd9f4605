#include "illum/render/debug_integrator.h"

#include "illum/render/bsdf.h"
#include "illum/render/material_eval.h"
#include "illum/render/tile_renderer.h"

namespace illum {

DebugIntegrator::DebugIntegrator(Mode mode, const Params& params) : mode_(mode) {
  if (mode_ == Mode::kDepth) normalize_depth_ = params.get<bool>("normalize", true);
}

Image DebugIntegrator::render(const RayTracer& tracer, const Camera& camera,
                              const RenderOptions& options) {
  const Scene& scene = tracer.scene();
  static constexpr const char* kNames[] = {"normals", "albedo", "depth"};
  const char* name = kNames[static_cast<int>(mode_)];
  warn_about_scene(scene, false, name);
  const float depth_scale = normalize_depth_ ? 1.0f / scene_scale(scene) : 1.0f;
  // Misses are black in every mode: 0 means "no surface".
  return render_tiles(camera, options, name, [&](const Ray& ray, SobolSampler&) -> Color {
    Hit hit;
    if (!tracer.intersect(ray, &hit)) return Color(0.0f);
    if (mode_ == Mode::kDepth) return Color(hit.t * glm::length(ray.direction) * depth_scale);
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    if (mode_ == Mode::kNormals) return 0.5f * si.ns + 0.5f;
    return material_reflectance(scene, interaction_material(scene, si), si);
  });
}

}  // namespace illum
