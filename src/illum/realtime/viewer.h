// Interactive window for `illum view`: GLFW window + Vulkan swapchain; each frame the
// renderer's 8-bit output is blitted to the swapchain image. Controls: W/A/S/D/Q/E move,
// right mouse button + drag looks around, 1/2 forward/deferred, 3–6 shadows none/map/
// vsm/volume, T cycles the tone mapper, B toggles bloom, H toggles Half-Lambert, Esc quits.
// The ImGui panel is not implemented.
#pragma once

#include <string>

#include "illum/realtime/renderer.h"

namespace illum::realtime {

// Opens the window and runs until it is closed. Returns false without side effects when no
// window can be opened (no display, no GLFW Vulkan support); `reason` says why.
bool run_viewer(const Scene& scene, const RendererOptions& options, std::string* reason);

}  // namespace illum::realtime
