// Vulkan result checking: a failed call throws illum::Error naming the call and the result.
#pragma once

#include <vulkan/vulkan.h>

#include "illum/core/error.h"

namespace illum::gpu {

const char* to_string(VkResult result);

[[noreturn]] void throw_vk_error(const char* call, VkResult result);

}  // namespace illum::gpu

#define ILLUM_VK(call)                                       \
  do {                                                       \
    const VkResult illum_vk_result_ = (call);                \
    if (illum_vk_result_ != VK_SUCCESS) [[unlikely]]         \
      ::illum::gpu::throw_vk_error(#call, illum_vk_result_); \
  } while (0)
