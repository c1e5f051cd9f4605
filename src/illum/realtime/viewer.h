// Interactive window for `illum view`: GLFW window + Vulkan swapchain. Each frame the
// renderer's 8-bit output is blitted to the swapchain image, then a Dear ImGui panel (every
// RendererOptions field, the lights, the camera and per-pass GPU ms) is drawn over it in
// its own small render pass (ImGui 1.86's Vulkan backend needs a VkRenderPass).
// Controls: W/A/S/D move, Q/E down/up, right mouse button + drag looks around, Shift moves
// faster, Esc quits; keys and mouse go to the panel while it has focus / the cursor.
#pragma once

#include <string>

#include "illum/realtime/renderer.h"

namespace illum::realtime {

struct ViewerOptions {
  int frames = 0;          // > 0: close the window after this many presented frames
  std::string screenshot;  // write the last presented image (scene + panel) here (.png)
};

// Opens the window and runs until it is closed. Returns false without side effects when no
// window can be opened (no display, no GLFW Vulkan support); `reason` says why. On exit it
// prints one summary line: frames, panel rectangle (pixels), validation message count.
bool run_viewer(const Scene& scene, const RendererOptions& options, const ViewerOptions& viewer,
                std::string* reason);

}  // namespace illum::realtime
