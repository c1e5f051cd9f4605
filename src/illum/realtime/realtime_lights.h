// The scene's lights as the real-time renderer uses them.
#pragma once

#include <vector>

#include "illum/scene/scene.h"

namespace illum::realtime {

// Point, spot and directional lights unchanged; each area light becomes a hemispherical spot
// light at its emitter's centroid, facing along the emitter's normal, with the far-field
// intensity of a Lambertian emitter, L·A·cos θ (Light::cosine_falloff; flux πLA).
// Environment lights are passed through unlit.
std::vector<Light> realtime_lights(const Scene& scene);
// Point, spot and directional lights: the ones the real-time passes light with (and that
// cast stencil shadows).
bool lit_in_real_time(const Light& light);

}  // namespace illum::realtime
