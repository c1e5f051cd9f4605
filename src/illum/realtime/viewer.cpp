#include "illum/realtime/viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "illum/core/log.h"
#include "illum/gpu/vk_check.h"

namespace illum::realtime {

namespace {

struct Glfw {
  bool ok = false;
  Glfw() : ok(glfwInit() == GLFW_TRUE) {}
  ~Glfw() {
    if (ok) glfwTerminate();
  }
};

struct Swapchain {
  VkDevice device = VK_NULL_HANDLE;
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  std::vector<VkImage> images;
  VkExtent2D extent{};
  ~Swapchain() {
    if (handle) vkDestroySwapchainKHR(device, handle, nullptr);
  }
};

void create_swapchain(gpu::Context& ctx, VkSurfaceKHR surface, GLFWwindow* window, Swapchain* sc) {
  VkSurfaceCapabilitiesKHR caps;
  ILLUM_VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physical(), surface, &caps));
  uint32_t count = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical(), surface, &count, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(count);
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical(), surface, &count, formats.data());
  // The renderer's output is already sRGB-encoded: present through a UNORM format.
  VkSurfaceFormatKHR format = formats.at(0);
  for (const auto& f : formats)
    if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) format = f;
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
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
  info.clipped = VK_TRUE;
  info.oldSwapchain = sc->handle;
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  ILLUM_VK(vkCreateSwapchainKHR(ctx.device(), &info, nullptr, &handle));
  if (sc->handle) vkDestroySwapchainKHR(ctx.device(), sc->handle, nullptr);
  sc->device = ctx.device();
  sc->handle = handle;
  sc->extent = extent;
  vkGetSwapchainImagesKHR(ctx.device(), handle, &count, nullptr);
  sc->images.resize(count);
  vkGetSwapchainImagesKHR(ctx.device(), handle, &count, sc->images.data());
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = src_stage;
  b.srcAccessMask = src_access;
  b.dstStageMask = dst_stage;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace

bool run_viewer(const Scene& scene, const RendererOptions& initial, std::string* reason) {
  Glfw glfw;
  if (!glfw.ok) {
    *reason = "GLFW could not initialise (no display?)";
    return false;
  }
  if (!glfwVulkanSupported()) {
    *reason = "GLFW reports no Vulkan support for windows";
    return false;
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  GLFWwindow* window =
      glfwCreateWindow(initial.width, initial.height, "illum view", nullptr, nullptr);
  if (!window) {
    *reason = "the window could not be created";
    return false;
  }
  struct WindowGuard {
    GLFWwindow* w;
    ~WindowGuard() { glfwDestroyWindow(w); }
  } window_guard{window};

  gpu::ContextOptions context_options;
  uint32_t ext_count = 0;
  const char** exts = glfwGetRequiredInstanceExtensions(&ext_count);
  for (uint32_t i = 0; i < ext_count; ++i)
    context_options.instance_extensions.emplace_back(exts[i]);
  gpu::Context ctx(context_options);
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  ILLUM_VK(glfwCreateWindowSurface(ctx.instance(), window, nullptr, &surface));
  struct SurfaceGuard {
    VkInstance i;
    VkSurfaceKHR s;
    ~SurfaceGuard() { vkDestroySurfaceKHR(i, s, nullptr); }
  } surface_guard{ctx.instance(), surface};
  VkBool32 present = VK_FALSE;
  vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical(), ctx.queue_family(), surface, &present);
  if (!present) {
    *reason = "the Vulkan queue cannot present to this window";
    return false;
  }
  auto swapchain = std::make_unique<Swapchain>();
  create_swapchain(ctx, surface, window, swapchain.get());

  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = ctx.queue_family();
  ILLUM_VK(vkCreateCommandPool(ctx.device(), &pi, nullptr, &pool));
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool;
  ai.commandBufferCount = 1;
  ILLUM_VK(vkAllocateCommandBuffers(ctx.device(), &ai, &cmd));
  VkSemaphore acquired = VK_NULL_HANDLE, done = VK_NULL_HANDLE;
  VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  ILLUM_VK(vkCreateSemaphore(ctx.device(), &si, nullptr, &acquired));
  ILLUM_VK(vkCreateSemaphore(ctx.device(), &si, nullptr, &done));
  VkFence fence = VK_NULL_HANDLE;
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  ILLUM_VK(vkCreateFence(ctx.device(), &fi, nullptr, &fence));
  struct SyncGuard {
    VkDevice d;
    VkCommandPool p;
    VkSemaphore a, b;
    VkFence f;
    ~SyncGuard() {
      vkDeviceWaitIdle(d);
      vkDestroyFence(d, f, nullptr);
      vkDestroySemaphore(d, a, nullptr);
      vkDestroySemaphore(d, b, nullptr);
      vkDestroyCommandPool(d, p, nullptr);
    }
  } sync_guard{ctx.device(), pool, acquired, done, fence};

  RendererOptions options = initial;
  Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  std::unique_ptr<Renderer> renderer;
  bool rebuild = true;
  const float speed = std::max(scene.bounds().diagonal(), 1e-3f) * 0.25f;
  double last_time = glfwGetTime(), last_x = 0.0, last_y = 0.0;
  bool dragging = false;
  int prev_keys[GLFW_KEY_LAST + 1] = {};
  auto pressed = [&](int key) {
    const int now = glfwGetKey(window, key);
    const bool edge = now == GLFW_PRESS && prev_keys[key] != GLFW_PRESS;
    prev_keys[key] = now;
    return edge;
  };
  std::printf(
      "illum view: W/A/S/D/Q/E move, right-drag look, 1/2 forward/deferred, 3-6 shadows "
      "none/map/vsm/volume, T tone mapper, B bloom, H Half-Lambert, Esc quit\n");
  while (!glfwWindowShouldClose(window)) {
    glfwPollEvents();
    if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
    const double now = glfwGetTime();
    const float dt = static_cast<float>(now - last_time);
    last_time = now;
    // Camera controls.
    vec3 forward = glm::normalize(camera.look_at - camera.position);
    const vec3 right = glm::normalize(glm::cross(forward, camera.up));
    vec3 move(0.0f);
    if (glfwGetKey(window, GLFW_KEY_W) == GLFW_PRESS) move += forward;
    if (glfwGetKey(window, GLFW_KEY_S) == GLFW_PRESS) move -= forward;
    if (glfwGetKey(window, GLFW_KEY_D) == GLFW_PRESS) move += right;
    if (glfwGetKey(window, GLFW_KEY_A) == GLFW_PRESS) move -= right;
    if (glfwGetKey(window, GLFW_KEY_E) == GLFW_PRESS) move += camera.up;
    if (glfwGetKey(window, GLFW_KEY_Q) == GLFW_PRESS) move -= camera.up;
    camera.position += move * speed * dt;
    camera.look_at += move * speed * dt;
    double mx, my;
    glfwGetCursorPos(window, &mx, &my);
    if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
      if (dragging) {
        const float yaw = -0.005f * static_cast<float>(mx - last_x);
        const float pitch = -0.005f * static_cast<float>(my - last_y);
        const float dist = glm::length(camera.look_at - camera.position);
        forward = glm::rotate(mat4(1.0f), yaw, camera.up) * vec4(forward, 0.0f);
        const vec3 r2 = glm::normalize(glm::cross(forward, camera.up));
        const vec3 pitched = glm::rotate(mat4(1.0f), pitch, r2) * vec4(forward, 0.0f);
        if (std::abs(glm::dot(glm::normalize(pitched), camera.up)) < 0.98f) forward = pitched;
        camera.look_at = camera.position + glm::normalize(forward) * dist;
      }
      dragging = true;
    } else {
      dragging = false;
    }
    last_x = mx;
    last_y = my;
    // Technique switches rebuild the renderer.
    if (pressed(GLFW_KEY_1)) options.technique = Technique::kForward, rebuild = true;
    if (pressed(GLFW_KEY_2)) options.technique = Technique::kDeferred, rebuild = true;
    if (pressed(GLFW_KEY_3)) options.shadows = ShadowMode::kNone, rebuild = true;
    if (pressed(GLFW_KEY_4)) options.shadows = ShadowMode::kMap, rebuild = true;
    if (pressed(GLFW_KEY_5)) options.shadows = ShadowMode::kVsm, rebuild = true;
    if (pressed(GLFW_KEY_6)) options.shadows = ShadowMode::kVolume, rebuild = true;
    if (pressed(GLFW_KEY_T))
      options.tone_mapper = static_cast<ToneMapOp>((static_cast<int>(options.tone_mapper) + 1) % 4),
      rebuild = true;
    if (pressed(GLFW_KEY_B))
      options.bloom_strength = options.bloom_strength > 0.0f ? 0.0f : 0.3f, rebuild = true;
    if (pressed(GLFW_KEY_H)) options.half_lambert = !options.half_lambert, rebuild = true;
    if (options.technique == Technique::kDeferred && options.shadows == ShadowMode::kVolume)
      options.shadows = ShadowMode::kMap;

    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    if (fw == 0 || fh == 0) continue;  // minimised
    if (static_cast<uint32_t>(fw) != swapchain->extent.width ||
        static_cast<uint32_t>(fh) != swapchain->extent.height) {
      ctx.wait_idle();
      create_swapchain(ctx, surface, window, swapchain.get());
      rebuild = true;
    }
    if (rebuild) {
      ctx.wait_idle();
      options.width = static_cast<int>(swapchain->extent.width);
      options.height = static_cast<int>(swapchain->extent.height);
      renderer.reset();
      renderer = std::make_unique<Renderer>(ctx, scene, options);
      rebuild = false;
    }
    renderer->render(camera);

    uint32_t index = 0;
    const VkResult acquire = vkAcquireNextImageKHR(ctx.device(), swapchain->handle, UINT64_MAX,
                                                   acquired, VK_NULL_HANDLE, &index);
    if (acquire == VK_ERROR_OUT_OF_DATE_KHR) {
      rebuild = true;
      ctx.wait_idle();
      create_swapchain(ctx, surface, window, swapchain.get());
      continue;
    }
    if (acquire != VK_SUBOPTIMAL_KHR) ILLUM_VK(acquire);
    ILLUM_VK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    ILLUM_VK(vkBeginCommandBuffer(cmd, &begin));
    gpu::GpuImage& out = renderer->output_image();
    out.transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkImage target = swapchain->images[index];
    image_barrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE,
                  VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.srcOffsets[1] = {static_cast<int32_t>(out.desc().width),
                          static_cast<int32_t>(out.desc().height), 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.dstOffsets[1] = {static_cast<int32_t>(swapchain->extent.width),
                          static_cast<int32_t>(swapchain->extent.height), 1};
    vkCmdBlitImage(cmd, out.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
    image_barrier(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT,
                  VK_ACCESS_2_NONE);
    ILLUM_VK(vkEndCommandBuffer(cmd));
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = acquired;
    wait.stageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = done;
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cb.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &wait;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cb;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    ILLUM_VK(vkQueueSubmit2(ctx.queue(), 1, &submit, fence));
    VkPresentInfoKHR pinfo{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pinfo.waitSemaphoreCount = 1;
    pinfo.pWaitSemaphores = &done;
    pinfo.swapchainCount = 1;
    pinfo.pSwapchains = &swapchain->handle;
    pinfo.pImageIndices = &index;
    const VkResult pr = vkQueuePresentKHR(ctx.queue(), &pinfo);
    ILLUM_VK(vkWaitForFences(ctx.device(), 1, &fence, VK_TRUE, UINT64_MAX));
    ILLUM_VK(vkResetFences(ctx.device(), 1, &fence));
    if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR)
      rebuild = true;
    else
      ILLUM_VK(pr);
    std::string title =
        fmt::format("illum view — {} {} shadows, {:.1f} ms",
                    options.technique == Technique::kForward ? "forward" : "deferred",
                    options.shadows == ShadowMode::kNone  ? "no"
                    : options.shadows == ShadowMode::kMap ? "map"
                    : options.shadows == ShadowMode::kVsm ? "vsm"
                                                          : "volume",
                    dt * 1000.0f);
    glfwSetWindowTitle(window, title.c_str());
  }
  renderer.reset();
  swapchain.reset();
  return true;
}

}  // namespace illum::realtime
