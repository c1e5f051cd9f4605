// Per-pass GPU time from timestamp queries: scope(cmd, name) writes a timestamp before and
// after the pass; resolve() reads them back (after the frame's fence) as milliseconds.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/context.h"

namespace illum::gpu {

struct PassTime {
  std::string name;
  double ms = 0.0;
};

class GpuTimer {
 public:
  GpuTimer(Context& context, uint32_t max_scopes = 64);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  bool supported() const { return pool_ != VK_NULL_HANDLE; }
  void reset(VkCommandBuffer cmd);  // start of a frame
  uint32_t begin(VkCommandBuffer cmd, const std::string& name);
  void end(VkCommandBuffer cmd, uint32_t scope);
  std::vector<PassTime> resolve() const;  // call after the frame has completed

 private:
  Context* context_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t max_scopes_;
  std::vector<std::string> names_;
};

}  // namespace illum::gpu
