// What every offline renderer does before its first ray: check the options, pick a camera
// for scenes without one, and warn (once per render) about scenes that cannot show much.
#pragma once

#include "illum/render/integrator.h"
#include "illum/scene/camera.h"
#include "illum/scene/scene.h"

namespace illum {

// Throws illum::Error naming the option (--width, --height, --spp, --threads, --time)
// when a value is out of range.
void validate_render_options(const RenderOptions& options);

// A camera looking at the centre of `bounds` along −z from in front of it, far enough that
// the bounding sphere fits the vertical field of view of an image with `aspect` = w/h.
// An empty box frames the unit cube around the origin.
Camera framing_camera(const Bounds3& bounds, float aspect = 1.0f);

// The scene's own camera if it has one, else framing_camera(scene bounds).
Camera scene_camera(const Scene& scene, float aspect = 1.0f);

// Length of the scene's bounding-box diagonal, or 1 for an empty scene (a usable scale
// for ray offsets, AO distances and depth normalization).
float scene_scale(const Scene& scene);

// Logs warnings for an empty scene and, when `needs_lights`, for a scene with no light
// (neither lights nor environment): such scenes render black rather than failing.
void warn_about_scene(const Scene& scene, bool needs_lights, const char* integrator);

}  // namespace illum
