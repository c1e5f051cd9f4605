// Bad input to the real-time renderer, refused at its entry with an illum::Error naming the
// option, light, material, mesh or camera field, before anything reaches the GPU: a NaN
// light position becomes NaN pixels (or, through a shadow map's far plane, a validation
// error), a zero-sized target an invalid Vulkan image, an index past a vertex buffer an
// out-of-bounds read the driver need not catch. Scene files are checked by their loaders
// already; these checks hold for scenes built in code and for every later change
// (update_lights, configure, each frame's camera).
#pragma once

#include <vector>

#include "illum/realtime/realtime_lights.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

// Geometry and materials: finite positions, indices inside their mesh, instances naming an
// existing mesh with a finite transform, finite non-negative colours.
void check_realtime_scene(const Scene& scene);
// Lights as realtime_lights() made them: finite positions, unit-able directions, finite
// non-negative intensity / irradiance, a spot cone in (0, 90°], a finite range ≥ 0.
void check_realtime_lights(const std::vector<Light>& lights);
// `single_light` (lighting.single_light), when ≥ 0, must name one of `light_count` lights.
// (The ranges of every other parameter are checked when RenderSettings takes a value.)
void check_single_light(int single_light, size_t light_count);
// The scene's part of the above, as the Renderer and the viewer run it at their entry:
// geometry, materials, realtime_lights(scene) and single_light, each message prefixed with
// the scene's file when it has one.
void check_realtime_input(const Scene& scene, int single_light);
// A finite position, look_at and up, a view direction that is not zero or parallel to up,
// and a vertical field of view in (0, 180°).
void check_camera(const Camera& camera);

}  // namespace illum::realtime
