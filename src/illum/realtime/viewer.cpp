#include "illum/realtime/viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/log.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/vk_check.h"
#include "illum/realtime/renderer_input.h"
#include "illum/realtime/viewer_panel.h"

namespace illum::realtime {

namespace {

// GLFW reports failures through a callback without user data; the last one is kept so the
// headless fallback can say why (e.g. "X11: The DISPLAY environment variable is missing").
std::string g_glfw_error;

void remember_glfw_error(int /*code*/, const char* description) {
  g_glfw_error = description ? description : "";
}

struct Glfw {
  bool ok = false;
  Glfw() {
    g_glfw_error.clear();
    glfwSetErrorCallback(remember_glfw_error);
    ok = glfwInit() == GLFW_TRUE;
  }
  ~Glfw() {
    if (ok) glfwTerminate();
    glfwSetErrorCallback(nullptr);
  }
};

std::string glfw_failure(const char* what) {
  return g_glfw_error.empty() ? std::string(what) : fmt::format("{}: {}", what, g_glfw_error);
}

constexpr float kLookRadiansPerPixel = 0.005f;
// Looking further up or down than this would make the view direction nearly parallel to
// the camera's up vector, where yaw spins around the view instead of turning it.
constexpr float kMaxElevation = glm::radians(80.0f);

// Turns the view by `yaw` about the camera's up vector (positive: to the left) and raises
// it by `pitch`, keeping the elevation within ±kMaxElevation (or within where it started,
// for a scene camera beyond that) so a fast drag stops short of the pole rather than
// flipping over it. Yaw changes only the azimuth and pitch only the elevation, so the
// result depends on the summed drag, not on how the frames split it.
void look_around(Camera* camera, float yaw, float pitch) {
  const vec3 up = glm::normalize(camera->up);
  const vec3 to_target = camera->look_at - camera->position;
  const float distance = glm::length(to_target);
  const vec3 forward = to_target / distance;
  const float sine = std::clamp(glm::dot(forward, up), -1.0f, 1.0f);
  const vec3 level = forward - sine * up;
  if (glm::length(level) < 1e-6f) return;  // looking along up: no azimuth to turn
  const vec3 azimuth = vec3(glm::rotate(mat4(1.0f), yaw, up) * vec4(glm::normalize(level), 0.0f));
  const float elevation = std::asin(sine);
  const float limit = std::max(kMaxElevation, std::abs(elevation));
  const float raised = std::clamp(elevation + pitch, -limit, limit);
  camera->look_at =
      camera->position + distance * (std::cos(raised) * azimuth + std::sin(raised) * up);
}

// Input handled by GLFW callbacks in the order the events arrive, not by polling once a
// frame: with frames of 100s of ms (lavapipe) a key tapped between two polls (Esc, R, C)
// was missed, the part of a drag made before the first frame that saw the button was
// lost, and C pressed right after a drag printed the camera without it. Held movement keys
// are still polled each frame (speed × frame time).
struct ViewerInput {
  Camera* camera = nullptr;
  Camera home;  // R puts the camera back here
  // From the last ImGui frame: the panel's rectangle, whether one of its popups (a combo's
  // list) is open, whether a widget edits text (ImGui's WantCaptureKeyboard).
  ImVec2 panel_min{0, 0}, panel_max{0, 0};
  bool popup_open = false, panel_wants_keyboard = false;
  double cursor_x = 0.0, cursor_y = 0.0;  // the last cursor position reported
  bool dragging = false;                  // right button held since a press off the panel
  bool quit = false;
};

ViewerInput& input_of(GLFWwindow* window) {
  return *static_cast<ViewerInput*>(glfwGetWindowUserPointer(window));
}

void print_camera(const Camera& camera) {
  std::printf("illum view: camera %s\n", camera_json(camera).c_str());
  std::fflush(stdout);
}

void on_cursor(GLFWwindow* window, double x, double y) {
  ViewerInput& in = input_of(window);
  // Dragging right turns right, dragging down looks down (window y grows downwards).
  if (in.dragging)
    look_around(in.camera, -kLookRadiansPerPixel * static_cast<float>(x - in.cursor_x),
                -kLookRadiansPerPixel * static_cast<float>(y - in.cursor_y));
  in.cursor_x = x;
  in.cursor_y = y;
}

void on_mouse_button(GLFWwindow* window, int button, int action, int /*mods*/) {
  if (button != GLFW_MOUSE_BUTTON_RIGHT) return;
  ViewerInput& in = input_of(window);
  if (action == GLFW_RELEASE) {
    in.dragging = false;
    return;
  }
  // ImGui's own rule (WantCaptureMouse: a press over its window, or while a popup is open,
  // is its), applied at the press itself: io.WantCaptureMouse is one frame old, and stays
  // true until the frame after a drag on the panel ends, swallowing a quick next drag.
  const bool over_panel = in.cursor_x >= in.panel_min.x && in.cursor_x < in.panel_max.x &&
                          in.cursor_y >= in.panel_min.y && in.cursor_y < in.panel_max.y;
  in.dragging = !over_panel && !in.popup_open;
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  ViewerInput& in = input_of(window);
  if (action != GLFW_PRESS || in.panel_wants_keyboard) return;
  if (key == GLFW_KEY_ESCAPE) in.quit = true;
  if (key == GLFW_KEY_R) *in.camera = in.home;
  if (key == GLFW_KEY_C) print_camera(*in.camera);
}

struct Swapchain {
  VkDevice device = VK_NULL_HANDLE;
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  std::vector<VkImage> images;
  std::vector<VkImageView> views;
  std::vector<VkFramebuffer> framebuffers;  // for the panel's render pass
  VkExtent2D extent{};
  void destroy_targets() {
    for (VkFramebuffer f : framebuffers) vkDestroyFramebuffer(device, f, nullptr);
    for (VkImageView v : views) vkDestroyImageView(device, v, nullptr);
    framebuffers.clear();
    views.clear();
  }
  ~Swapchain() {
    destroy_targets();
    if (handle) vkDestroySwapchainKHR(device, handle, nullptr);
  }
};

VkSurfaceFormatKHR pick_surface_format(gpu::Context& ctx, VkSurfaceKHR surface) {
  uint32_t count = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical(), surface, &count, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(count);
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical(), surface, &count, formats.data());
  if (formats.empty()) throw Error("illum view: the window surface offers no formats");
  // The renderer's output is already sRGB-encoded, and ImGui's colours are display values:
  // present through a UNORM format so neither is encoded twice.
  VkSurfaceFormatKHR format = formats.at(0);
  for (const auto& f : formats)
    if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) format = f;
  return format;
}

// The panel's pass: draws over the blitted frame (load), then leaves the image ready to
// present. Frames written to a screenshot get one more barrier and a copy after it.
VkRenderPass create_overlay_pass(VkDevice device, VkFormat format) {
  VkAttachmentDescription color{};
  color.format = format;
  color.samples = VK_SAMPLE_COUNT_1_BIT;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  color.initialLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  color.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &ref;
  VkSubpassDependency deps[2]{};
  deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  deps[0].dstSubpass = 0;
  deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  deps[0].srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  deps[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  deps[0].dstAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  deps[1].srcSubpass = 0;
  deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 1;
  info.pAttachments = &color;
  info.subpassCount = 1;
  info.pSubpasses = &sub;
  info.dependencyCount = 2;
  info.pDependencies = deps;
  VkRenderPass pass = VK_NULL_HANDLE;
  ILLUM_VK(vkCreateRenderPass(device, &info, nullptr, &pass));
  return pass;
}

void create_swapchain(gpu::Context& ctx, VkSurfaceKHR surface, GLFWwindow* window,
                      VkSurfaceFormatKHR format, VkRenderPass pass, bool readback, Swapchain* sc) {
  VkSurfaceCapabilitiesKHR caps;
  ILLUM_VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physical(), surface, &caps));
  uint32_t count = 0;
  const VkImageUsageFlags usage =
      VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
      (readback ? VkImageUsageFlags{VK_IMAGE_USAGE_TRANSFER_SRC_BIT} : VkImageUsageFlags{0});
  if ((caps.supportedUsageFlags & usage) != usage)
    throw Error(readback ? "illum view --screenshot: the window's swapchain cannot be read back"
                         : "illum view: the window's swapchain cannot be rendered to");
  int w = 0, h = 0;
  glfwGetFramebufferSize(window, &w, &h);
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == UINT32_MAX)
    extent = {
        std::clamp(static_cast<uint32_t>(w), caps.minImageExtent.width, caps.maxImageExtent.width),
        std::clamp(static_cast<uint32_t>(h), caps.minImageExtent.height,
                   caps.maxImageExtent.height)};
  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface;
  info.minImageCount = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = usage;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
  info.clipped = VK_TRUE;
  info.oldSwapchain = sc->handle;
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  ILLUM_VK(vkCreateSwapchainKHR(ctx.device(), &info, nullptr, &handle));
  // Views and framebuffers of the old images go before the old swapchain itself.
  sc->device = ctx.device();
  sc->destroy_targets();
  if (sc->handle) vkDestroySwapchainKHR(ctx.device(), sc->handle, nullptr);
  sc->device = ctx.device();
  sc->handle = handle;
  sc->extent = extent;
  vkGetSwapchainImagesKHR(ctx.device(), handle, &count, nullptr);
  sc->images.resize(count);
  vkGetSwapchainImagesKHR(ctx.device(), handle, &count, sc->images.data());
  sc->format = format.format;
  for (VkImage image : sc->images) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format.format;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view = VK_NULL_HANDLE;
    ILLUM_VK(vkCreateImageView(ctx.device(), &vi, nullptr, &view));
    sc->views.push_back(view);
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = pass;
    fi.attachmentCount = 1;
    fi.pAttachments = &view;
    fi.width = extent.width;
    fi.height = extent.height;
    fi.layers = 1;
    VkFramebuffer fb = VK_NULL_HANDLE;
    ILLUM_VK(vkCreateFramebuffer(ctx.device(), &fi, nullptr, &fb));
    sc->framebuffers.push_back(fb);
  }
}

// Swapchain images: one colour mip, one layer.
constexpr VkImageSubresourceRange kSwapchainRange{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};

// The ImGui context and its two backends, shut down in reverse order. No imgui.ini is
// written to the user's folder.
struct ImGuiSession {
  bool glfw = false, vulkan = false;
  ImGuiSession() {
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
  }
  ~ImGuiSession() {
    if (vulkan) ImGui_ImplVulkan_Shutdown();
    if (glfw) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
};

void check_vk(VkResult r) {
  if (r != VK_SUCCESS)
    throw Error(fmt::format("illum view: ImGui Vulkan call failed ({})", static_cast<int>(r)));
}

struct WindowGuard {
  GLFWwindow* w = nullptr;
  ~WindowGuard() {
    if (w) glfwDestroyWindow(w);
  }
};

struct SurfaceGuard {
  VkInstance i;
  VkSurfaceKHR s;
  ~SurfaceGuard() { vkDestroySurfaceKHR(i, s, nullptr); }
};

// A Vulkan-capable window of the settings' size (GLFW must be initialised); false with the
// reason when there is none.
bool open_window(const RenderSettings& initial, WindowGuard* window, std::string* reason) {
  if (!glfwVulkanSupported()) {
    *reason = glfw_failure("GLFW reports no Vulkan support for windows");
    return false;
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window->w = glfwCreateWindow(initial.width, initial.height, "illum view", nullptr, nullptr);
  if (!window->w) {
    *reason = glfw_failure("the window could not be created");
    return false;
  }
  return true;
}

// The device with the instance extensions the window system needs.
gpu::ContextOptions window_context_options() {
  gpu::ContextOptions options;
  uint32_t ext_count = 0;
  const char** exts = glfwGetRequiredInstanceExtensions(&ext_count);
  for (uint32_t i = 0; i < ext_count; ++i) options.instance_extensions.emplace_back(exts[i]);
  return options;
}

// Whether the screenshot's bytes are BGRA; throws when a screenshot is asked for and the
// window's format is not 8-bit RGBA/BGRA.
bool screenshot_is_bgra(VkFormat format, bool readback) {
  if (readback && format != VK_FORMAT_B8G8R8A8_UNORM && format != VK_FORMAT_R8G8B8A8_UNORM &&
      format != VK_FORMAT_B8G8R8A8_SRGB && format != VK_FORMAT_R8G8B8A8_SRGB)
    throw Error("illum view --screenshot: the window's format is not 8-bit RGBA/BGRA");
  return format == VK_FORMAT_B8G8R8A8_UNORM || format == VK_FORMAT_B8G8R8A8_SRGB;
}

// What the present loop records and synchronises with: one command buffer, the acquire and
// render-done semaphores, the frame's fence, the panel's render pass and ImGui's descriptor
// pool (only the font texture's set comes from it). Destroyed after the device is idle.
struct PresentObjects {
  VkDevice device = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkSemaphore acquired = VK_NULL_HANDLE, done = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  VkRenderPass overlay_pass = VK_NULL_HANDLE;
  VkDescriptorPool imgui_pool = VK_NULL_HANDLE;

  PresentObjects(gpu::Context& ctx, VkFormat format) : device(ctx.device()) {
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = ctx.queue_family();
    ILLUM_VK(vkCreateCommandPool(device, &pi, nullptr, &pool));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.commandBufferCount = 1;
    ILLUM_VK(vkAllocateCommandBuffers(device, &ai, &cmd));
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    ILLUM_VK(vkCreateSemaphore(device, &si, nullptr, &acquired));
    ILLUM_VK(vkCreateSemaphore(device, &si, nullptr, &done));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    ILLUM_VK(vkCreateFence(device, &fi, nullptr, &fence));
    overlay_pass = create_overlay_pass(device, format);
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
    VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dp.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    dp.maxSets = 4;
    dp.poolSizeCount = 1;
    dp.pPoolSizes = &size;
    ILLUM_VK(vkCreateDescriptorPool(device, &dp, nullptr, &imgui_pool));
  }
  PresentObjects(const PresentObjects&) = delete;
  PresentObjects& operator=(const PresentObjects&) = delete;
  ~PresentObjects() {
    vkDeviceWaitIdle(device);
    vkDestroyDescriptorPool(device, imgui_pool, nullptr);
    vkDestroyRenderPass(device, overlay_pass, nullptr);
    vkDestroyFence(device, fence, nullptr);
    vkDestroySemaphore(device, acquired, nullptr);
    vkDestroySemaphore(device, done, nullptr);
    vkDestroyCommandPool(device, pool, nullptr);
  }
};

// Our input callbacks first: ImGui's backend installs its own and chains to these.
void install_input(GLFWwindow* window, ViewerInput* input) {
  glfwSetWindowUserPointer(window, input);
  glfwGetCursorPos(window, &input->cursor_x, &input->cursor_y);
  glfwSetCursorPosCallback(window, on_cursor);
  glfwSetMouseButtonCallback(window, on_mouse_button);
  glfwSetKeyCallback(window, on_key);
}

void init_imgui_backends(ImGuiSession& imgui, GLFWwindow* window, gpu::Context& ctx,
                         const PresentObjects& present) {
  imgui.glfw = ImGui_ImplGlfw_InitForVulkan(window, true);
  ImGui_ImplVulkan_InitInfo init{};
  init.Instance = ctx.instance();
  init.PhysicalDevice = ctx.physical();
  init.Device = ctx.device();
  init.QueueFamily = ctx.queue_family();
  init.Queue = ctx.queue();
  init.DescriptorPool = present.imgui_pool;
  init.Subpass = 0;
  // Every frame waits for its fence, so two sets of ImGui vertex buffers are plenty.
  init.MinImageCount = 2;
  init.ImageCount = 2;
  init.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  init.CheckVkResultFn = check_vk;
  imgui.vulkan = ImGui_ImplVulkan_Init(&init, present.overlay_pass);
  if (!imgui.glfw || !imgui.vulkan) throw Error("illum view: ImGui backends failed to initialise");
  ctx.immediate([](VkCommandBuffer c) { ImGui_ImplVulkan_CreateFontsTexture(c); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

// The loop's clock: frame intervals, their running mean for the panel, and the longest.
struct FrameClock {
  double start = 0.0, last = 0.0;
  double frame_ms = 0.0;
  // The first frame builds the renderer and the second's interval includes that; the
  // longest interval after them bounds how far input timing can be off by one frame.
  double longest_frame_s = 0.0;
  int frames = 0;

  // The seconds since the last tick.
  float tick() {
    const double now = glfwGetTime();
    const float dt = static_cast<float>(now - last);
    last = now;
    frame_ms = frame_ms == 0.0 ? dt * 1000.0 : 0.9 * frame_ms + 0.1 * dt * 1000.0;
    if (frames >= 2) longest_frame_s = std::max(longest_frame_s, static_cast<double>(dt));
    return dt;
  }
};

// Why the loop ends before this frame (nullptr: it goes on). Polls the window's events.
const char* loop_end(GLFWwindow* window, const ViewerOptions& viewer, const FrameClock& clock,
                     const ViewerInput& input) {
  if (glfwWindowShouldClose(window)) return "closing the window";
  if (viewer.frames > 0 && clock.frames >= viewer.frames) return "--close-after-frames";
  if (viewer.seconds > 0.0 && glfwGetTime() - clock.start >= viewer.seconds)
    return "--close-after-seconds";
  glfwPollEvents();
  if (input.quit) return "Esc";
  return nullptr;
}

// The panel's ImGui frame, drawn and rendered to draw data.
void build_panel_frame(gpu::Context& ctx, RenderSettings* settings, PanelState* panel,
                       Camera* camera, const Camera& home, const Renderer* renderer,
                       double frame_ms, ViewerInput* input) {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  static const std::vector<gpu::PassTime> kNoTimes;
  draw_panel(ctx, settings, panel, camera, home, renderer ? renderer->pass_times() : kNoTimes,
             frame_ms, std::min(340.0f, 0.5f * static_cast<float>(settings->width)),
             static_cast<float>(settings->height));
  input->popup_open = ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopup);
  ImGui::Render();
}

// Camera controls: held W/A/S/D/Q/E move (keys and the mouse belong to the panel while it
// wants them).
void move_camera(GLFWwindow* window, const PanelState& panel, float diagonal, float dt,
                 Camera* camera, ViewerInput* input) {
  const ImGuiIO& io = ImGui::GetIO();
  input->panel_wants_keyboard = io.WantCaptureKeyboard;
  input->panel_min = panel.panel_pos;
  input->panel_max =
      ImVec2(panel.panel_pos.x + panel.panel_size.x, panel.panel_pos.y + panel.panel_size.y);
  const bool shift = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                     glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  const float speed = diagonal * 0.25f * panel.speed * (shift ? 4.0f : 1.0f);
  const vec3 forward = glm::normalize(camera->look_at - camera->position);
  const vec3 right = glm::normalize(glm::cross(forward, camera->up));
  if (io.WantCaptureKeyboard) return;
  vec3 move(0.0f);
  if (glfwGetKey(window, GLFW_KEY_W) == GLFW_PRESS) move += forward;
  if (glfwGetKey(window, GLFW_KEY_S) == GLFW_PRESS) move -= forward;
  if (glfwGetKey(window, GLFW_KEY_D) == GLFW_PRESS) move += right;
  if (glfwGetKey(window, GLFW_KEY_A) == GLFW_PRESS) move -= right;
  if (glfwGetKey(window, GLFW_KEY_E) == GLFW_PRESS) move += camera->up;
  if (glfwGetKey(window, GLFW_KEY_Q) == GLFW_PRESS) move -= camera->up;
  camera->position += move * speed * dt;
  camera->look_at += move * speed * dt;
}

// The renderer applies per-frame values in place and rebuilds only the techniques whose
// structure changed (Renderer::configure); a change it refuses keeps the last settings.
void update_renderer(gpu::Context& ctx, const Scene& scene, const ViewerOptions& viewer,
                     RenderSettings* settings, PanelState* panel,
                     std::unique_ptr<Renderer>* renderer) {
  if (!*renderer) {
    *renderer = std::make_unique<Renderer>(ctx, scene, *settings);
    if (viewer.lightmap.kind != LightmapKind::kNone) (*renderer)->set_lightmap(viewer.lightmap);
    if (!viewer.prt.empty()) (*renderer)->set_prt(viewer.prt);
    panel->lights_changed = true;  // a new renderer starts from the scene's lights
  } else if (!(*settings == (*renderer)->settings())) {
    try {
      ctx.wait_idle();
      (*renderer)->configure(*settings);
      panel->error.clear();
    } catch (const Error& e) {
      panel->error = e.what();
      *settings = (*renderer)->settings();  // keep the working frame
    }
  }
  if (panel->lights_changed) {
    (*renderer)->update_lights(scaled_lights(*panel));
    panel->lights_changed = false;
  }
}

// The frame on the swapchain image: the renderer's output blitted over it, the panel drawn
// over that, and (for a screenshot) the result copied into `shot`.
void record_present(VkCommandBuffer cmd, Renderer& renderer, VkImage target,
                    VkFramebuffer framebuffer, VkExtent2D extent, VkRenderPass overlay_pass,
                    const gpu::Buffer* shot) {
  gpu::GpuImage& out = renderer.output_image();
  out.transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                 VK_ACCESS_2_TRANSFER_READ_BIT);
  gpu::image_barrier(cmd, target, kSwapchainRange, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                     VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {static_cast<int32_t>(out.desc().width),
                        static_cast<int32_t>(out.desc().height), 1};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.dstOffsets[1] = {static_cast<int32_t>(extent.width), static_cast<int32_t>(extent.height), 1};
  vkCmdBlitImage(cmd, out.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
  // The panel, drawn over the frame in the classic render pass ImGui 1.86 needs.
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = overlay_pass;
  rp.framebuffer = framebuffer;
  rp.renderArea = {{0, 0}, extent};
  vkCmdBeginRenderPass(cmd, &rp, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  vkCmdEndRenderPass(cmd);
  if (!shot) return;
  // The render pass's outgoing dependency made its writes visible to transfer reads.
  gpu::image_barrier(cmd, target, kSwapchainRange, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                     VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                     VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, shot->handle(), 1,
                         &region);
  gpu::image_barrier(cmd, target, kSwapchainRange, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                     VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT,
                     VK_ACCESS_2_NONE);
}

// Submits the recorded frame after the image is acquired, presents it once it is done, and
// returns the present's result.
VkResult submit_and_present(gpu::Context& ctx, const PresentObjects& present,
                            const VkSwapchainKHR& swapchain, const uint32_t& index) {
  VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  wait.semaphore = present.acquired;
  wait.stageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
  VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  signal.semaphore = present.done;
  signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cb.commandBuffer = present.cmd;
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.waitSemaphoreInfoCount = 1;
  submit.pWaitSemaphoreInfos = &wait;
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cb;
  submit.signalSemaphoreInfoCount = 1;
  submit.pSignalSemaphoreInfos = &signal;
  ILLUM_VK(vkQueueSubmit2(ctx.queue(), 1, &submit, present.fence));
  VkPresentInfoKHR pinfo{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  pinfo.waitSemaphoreCount = 1;
  pinfo.pWaitSemaphores = &present.done;
  pinfo.swapchainCount = 1;
  pinfo.pSwapchains = &swapchain;
  pinfo.pImageIndices = &index;
  return vkQueuePresentKHR(ctx.queue(), &pinfo);
}

// The last presented frame, written code for code (no sRGB re-encoding): what was on screen.
void write_screenshot(const gpu::Buffer& shot, VkExtent2D extent, bool bgra,
                      const std::string& path) {
  const int w = static_cast<int>(extent.width);
  const int h = static_cast<int>(extent.height);
  std::vector<uint8_t> bytes(shot.size());
  shot.read(bytes.data(), bytes.size());
  Image img(w, h, 4, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* px = &bytes[(static_cast<size_t>(y) * w + x) * 4];
      for (int c = 0; c < 3; ++c)
        img.pixel(x, y)[c] = static_cast<float>(px[bgra ? 2 - c : c]) / 255.0f;
    }
  ImageWriteOptions wo;
  wo.srgb = false;
  write_image(path, img, wo);
}

}  // namespace

std::string camera_json(const Camera& camera) {
  const auto v = [](const vec3& a) { return fmt::format("[{}, {}, {}]", a.x, a.y, a.z); };
  return fmt::format(R"({{"position": {}, "look_at": {}, "up": {}, "fov_y_deg": {}}})",
                     v(camera.position), v(camera.look_at), v(camera.up),
                     glm::degrees(camera.fov_y));
}

bool run_viewer(const Scene& scene, const RenderSettings& initial, const ViewerOptions& viewer,
                Camera* final_camera, std::string* reason) {
  // Bad input is refused before a window opens (GLFW would refuse a 0×0 window only as
  // "no window", and the caller would fall back to headless).
  initial.check();
  check_realtime_input(scene, initial.get<int>("lighting.single_light"));
  check_camera(scene.camera ? *scene.camera : Camera::framing(scene.bounds()));
  ViewerInput input;  // outlives the window, whose callbacks point at it
  Glfw glfw;
  if (!glfw.ok) {
    *reason = glfw_failure("GLFW could not initialise");
    return false;
  }
  WindowGuard window;
  if (!open_window(initial, &window, reason)) return false;

  gpu::Context ctx(window_context_options());
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  ILLUM_VK(glfwCreateWindowSurface(ctx.instance(), window.w, nullptr, &surface));
  const SurfaceGuard surface_guard{ctx.instance(), surface};
  VkBool32 can_present = VK_FALSE;
  vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical(), ctx.queue_family(), surface, &can_present);
  if (!can_present) {
    *reason = "the Vulkan queue cannot present to this window";
    return false;
  }
  const bool readback = !viewer.screenshot.empty();
  const VkSurfaceFormatKHR surface_format = pick_surface_format(ctx, surface);
  const bool bgra = screenshot_is_bgra(surface_format.format, readback);
  const PresentObjects present(ctx, surface_format.format);
  auto swapchain = std::make_unique<Swapchain>();
  const auto recreate_swapchain = [&] {
    create_swapchain(ctx, surface, window.w, surface_format, present.overlay_pass, readback,
                     swapchain.get());
  };
  recreate_swapchain();

  ImGuiSession imgui;
  const Camera home = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  Camera camera = home;
  input.camera = &camera;
  input.home = home;
  install_input(window.w, &input);
  init_imgui_backends(imgui, window.w, ctx, present);

  // Screenshot: every frame's final image is copied here (cheap), written at exit.
  gpu::Buffer shot;

  RenderSettings settings = initial;
  std::unique_ptr<Renderer> renderer;
  PanelState panel;
  panel.base_lights = realtime_lights(scene);
  panel.lights = panel.base_lights;
  const float diagonal = std::max(scene.bounds().diagonal(), 1e-3f);
  FrameClock clock;
  clock.start = clock.last = glfwGetTime();
  bool have_shot = false;
  const char* ended_by = "closing the window";
  while (true) {
    if (const char* end = loop_end(window.w, viewer, clock, input)) {
      ended_by = end;
      break;
    }
    const float dt = clock.tick();

    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window.w, &fw, &fh);
    if (fw == 0 || fh == 0) {  // minimised: wake now and then for --seconds
      glfwWaitEventsTimeout(0.1);
      continue;
    }
    if (static_cast<uint32_t>(fw) != swapchain->extent.width ||
        static_cast<uint32_t>(fh) != swapchain->extent.height) {
      ctx.wait_idle();
      recreate_swapchain();
    }
    settings.width = static_cast<int>(swapchain->extent.width);
    settings.height = static_cast<int>(swapchain->extent.height);

    build_panel_frame(ctx, &settings, &panel, &camera, home, renderer.get(), clock.frame_ms,
                      &input);
    move_camera(window.w, panel, diagonal, dt, &camera, &input);
    if (panel.print_camera) print_camera(camera);
    panel.print_camera = false;
    update_renderer(ctx, scene, viewer, &settings, &panel, &renderer);
    renderer->render(camera);

    uint32_t index = 0;
    const VkResult acquire = vkAcquireNextImageKHR(ctx.device(), swapchain->handle, UINT64_MAX,
                                                   present.acquired, VK_NULL_HANDLE, &index);
    if (acquire == VK_ERROR_OUT_OF_DATE_KHR) {
      ctx.wait_idle();
      recreate_swapchain();
      continue;
    }
    if (acquire != VK_SUBOPTIMAL_KHR) ILLUM_VK(acquire);
    const VkExtent2D extent = swapchain->extent;
    if (readback) {
      const VkDeviceSize bytes = VkDeviceSize{4} * extent.width * extent.height;
      if (shot.size() != bytes)
        shot =
            gpu::Buffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::kReadback);
    }
    ILLUM_VK(vkResetCommandBuffer(present.cmd, 0));
    gpu::record_one_time(present.cmd, [&](VkCommandBuffer cmd) {
      record_present(cmd, *renderer, swapchain->images[index], swapchain->framebuffers[index],
                     extent, present.overlay_pass, readback ? &shot : nullptr);
    });
    const VkResult pr = submit_and_present(ctx, present, swapchain->handle, index);
    ctx.wait_and_reset(present.fence);
    have_shot = readback;
    if (++clock.frames == 1) {
      std::printf(
          "illum view: first frame after %.0f ms; W/A/S/D/Q/E move (%.3g units/s, Shift x4), "
          "right-drag look, R reset camera, C print camera, Esc quits\n",
          1000.0 * (glfwGetTime() - clock.start), diagonal * 0.25f);
      std::fflush(stdout);
    }
    if (pr != VK_ERROR_OUT_OF_DATE_KHR && pr != VK_SUBOPTIMAL_KHR) ILLUM_VK(pr);
  }
  ctx.wait_idle();
  if (have_shot) write_screenshot(shot, swapchain->extent, bgra, viewer.screenshot);
  std::printf(
      "illum view: %d frames, %ux%u, panel at %d,%d size %dx%d, %zu validation messages%s, "
      "longest frame %.0f ms, ended by %s\n",
      clock.frames, swapchain->extent.width, swapchain->extent.height,
      static_cast<int>(panel.panel_pos.x), static_cast<int>(panel.panel_pos.y),
      static_cast<int>(panel.panel_size.x), static_cast<int>(panel.panel_size.y),
      ctx.validation_message_count(),
      ctx.validation_enabled() ? " (validation on)" : " (validation off)",
      1000.0 * clock.longest_frame_s, ended_by);
  if (have_shot) std::printf("  wrote %s\n", viewer.screenshot.c_str());
  std::fflush(stdout);
  renderer.reset();
  if (final_camera) *final_camera = camera;
  return true;
}

}  // namespace illum::realtime
