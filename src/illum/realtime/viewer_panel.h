// `illum view`'s Dear ImGui panel, generated from the technique declarations
// (technique_registry.h): the frame pipeline and shadow method as combos, each add-on as a
// switch, and one widget per declared parameter chosen by its type and UI hint (checkbox,
// slider — linear, logarithmic, over a power of two's exponent, over the light indices —,
// colour, combo); a '*' marks structural parameters (the renderer rebuilds their technique),
// the others apply at the next frame. Besides: the GPU times, the lights and the camera.
#pragma once

#include <string>
#include <vector>

#include <imgui.h>

#include "illum/gpu/context.h"
#include "illum/gpu/gpu_timer.h"
#include "illum/realtime/render_settings.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

// What the panel edits besides the RenderSettings.
struct PanelState {
  std::vector<Light> base_lights;  // realtime_lights(scene): what the edits start from
  std::vector<Light> lights;       // as edited
  float light_scale = 1.0f;        // multiplies every light's intensity / irradiance
  bool lights_changed = false;
  float speed = 1.0f;         // multiplies the camera speed (0.25 scene diagonals a second)
  bool print_camera = false;  // the panel's "print camera" button was pressed
  std::string error;          // the last rejected change (e.g. volume without depth clamp)
  ImVec2 panel_pos{0, 0}, panel_size{0, 0};
};

// The lights as edited, times the intensity multiplier.
std::vector<Light> scaled_lights(const PanelState& panel);

// Draws the panel; edits go into `settings` (checked against the declarations: a value the
// declaration refuses is not taken), `panel` and `camera`.
void draw_panel(const gpu::Context& ctx, RenderSettings* settings, PanelState* panel,
                Camera* camera, const Camera& home, const std::vector<gpu::PassTime>& times,
                double frame_ms, float panel_width, float panel_height);

}  // namespace illum::realtime
