// Interactive window for `illum view`: GLFW window + Vulkan swapchain. Each frame the
// renderer's 8-bit output is blitted to the swapchain image, then a Dear ImGui panel
// (viewer_panel.h: generated from the technique declarations, plus the lights, the camera
// and per-pass GPU ms) is drawn over it in its own small render pass (ImGui 1.86's Vulkan
// backend needs a VkRenderPass).
// Controls: W/A/S/D move, Q/E down/up (0.25 scene diagonals a second; Shift ×4), right
// mouse button + drag looks around (0.005 rad a pixel, pitch within ±80°), R resets the
// camera, C prints it, Esc quits. A drag that starts over the panel belongs to the panel
// (ImGui's WantCaptureMouse), and keys go to the panel while one of its widgets edits text.
#pragma once

#include <string>

#include "illum/realtime/renderer.h"

namespace illum::realtime {

struct ViewerOptions {
  int frames = 0;          // > 0: close the window after this many presented frames
  double seconds = 0.0;    // > 0: close the window after this many seconds
  std::string screenshot;  // write the last presented image (scene + panel) here (.png)
  Lightmap lightmap;       // baked light-map shown by every renderer the viewer builds
  PrtTransfer prt;         // baked PRT transfer, likewise (empty: none)
};

// Opens the window and runs until it is closed. Returns false without side effects when no
// window can be opened (no display, no GLFW Vulkan support); `reason` says why. On exit it
// prints one summary line: frames, panel rectangle (pixels), validation message count,
// longest frame, what ended it; `final_camera` (may be null) receives the camera as left.
bool run_viewer(const Scene& scene, const RenderSettings& settings, const ViewerOptions& viewer,
                Camera* final_camera, std::string* reason);

// The camera as the scene file's "camera" object on one line (position, look_at, up,
// fov_y_deg; shortest round-trip decimals), ready to paste into a .illum.json file.
std::string camera_json(const Camera& camera);

}  // namespace illum::realtime
