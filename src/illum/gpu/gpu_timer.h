// Per-pass GPU time from timestamp queries: begin(cmd, name) writes a timestamp, end() the
// matching one; resolve() reads them back (after the frame's fence) as milliseconds. Scopes
// nest (a pass's per-light steps inside the pass): each PassTime says how deep it sits, so
// totals add up depth 0 only. reserve() grows the query pool before a frame that needs
// more scopes than it holds.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/context.h"

namespace illum::gpu {

struct PassTime {
  std::string name;
  double ms = 0.0;
  int depth = 0;  // 0: a pass; 1: a step inside the enclosing depth-0 scope; ...
};

class GpuTimer {
 public:
  GpuTimer(Context& context, uint32_t max_scopes = 64);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  bool supported() const { return pool_ != VK_NULL_HANDLE; }
  uint32_t capacity() const { return max_scopes_; }
  // Makes room for `scopes` scopes a frame; call outside command recording (it may recreate
  // the query pool, which no pending work may use).
  void reserve(uint32_t scopes);
  void reset(VkCommandBuffer cmd);  // start of a frame
  uint32_t begin(VkCommandBuffer cmd, const std::string& name);
  void end(VkCommandBuffer cmd, uint32_t scope);
  std::vector<PassTime> resolve() const;  // call after the frame has completed

 private:
  void create_pool();

  Context* context_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t max_scopes_;
  std::vector<std::string> names_;
  std::vector<int> depths_;
  int open_ = 0;  // scopes begun and not yet ended
};

}  // namespace illum::gpu
