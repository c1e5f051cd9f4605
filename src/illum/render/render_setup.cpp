#include "illum/render/render_setup.h"

#include <algorithm>
#include <cmath>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/lighting_overrides.h"

namespace illum {

void validate_render_options(const RenderOptions& o) {
  if (o.width < 1 || o.width > kMaxImageSide)
    throw Error(fmt::format("--width {} is out of range [1, {}]", o.width, kMaxImageSide));
  if (o.height < 1 || o.height > kMaxImageSide)
    throw Error(fmt::format("--height {} is out of range [1, {}]", o.height, kMaxImageSide));
  if (o.spp < 1) throw Error(fmt::format("--spp {} must be at least 1", o.spp));
  if (o.threads < 0)
    throw Error(fmt::format("--threads {} must be 0 (all cores) or more", o.threads));
  if (!std::isfinite(o.time_budget_s) || o.time_budget_s < 0.0)
    throw Error(fmt::format("--time {} must be a finite number of seconds ≥ 0", o.time_budget_s));
}

Camera framing_camera(const Bounds3& bounds, float aspect) {
  Bounds3 b = bounds;
  if (b.empty()) {
    b.extend(vec3(-1.0f));
    b.extend(vec3(1.0f));
  }
  Camera cam;
  const float radius = std::max(0.5f * b.diagonal(), 1e-6f);
  // Fit the bounding sphere in the narrower of the two fields of view.
  const float half_v = 0.5f * cam.fov_y;
  const float half_h = std::atan(std::tan(half_v) * std::max(aspect, 1e-3f));
  const float half = std::min(half_v, half_h);
  const float distance = radius / std::sin(half);
  cam.look_at = b.center();
  cam.position = b.center() + vec3(0.0f, 0.0f, distance);
  cam.up = vec3(0.0f, 1.0f, 0.0f);
  return cam;
}

Camera scene_camera(const Scene& scene, float aspect) {
  if (scene.camera) return *scene.camera;
  return framing_camera(scene.bounds(), aspect);
}

float scene_scale(const Scene& scene) {
  const Bounds3 b = scene.bounds();
  const float d = b.diagonal();
  return b.empty() || !(d > 0.0f) ? 1.0f : d;
}

void warn_about_scene(const Scene& scene, bool needs_lights, const char* integrator) {
  if (scene.triangle_count() == 0)
    log::warn("{}: scene '{}' has no geometry; only the background will show", integrator,
              scene.name);
  if (needs_lights && !has_any_light(scene))
    log::warn("{}", unlit_scene_message(scene, integrator));
}

}  // namespace illum
