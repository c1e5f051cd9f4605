#include "illum/gpu/gpu_timer.h"

#include <algorithm>

#include "illum/gpu/vk_check.h"

namespace illum::gpu {

GpuTimer::GpuTimer(Context& context, uint32_t max_scopes)
    : context_(&context), max_scopes_(max_scopes) {
  create_pool();
}

GpuTimer::~GpuTimer() {
  if (pool_) vkDestroyQueryPool(context_->device(), pool_, nullptr);
}

void GpuTimer::create_pool() {
  if (pool_) vkDestroyQueryPool(context_->device(), pool_, nullptr);
  pool_ = VK_NULL_HANDLE;
  if (!context_->timestamps()) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * max_scopes_;
  ILLUM_VK(vkCreateQueryPool(context_->device(), &info, nullptr, &pool_));
}

void GpuTimer::reserve(uint32_t scopes) {
  if (scopes <= max_scopes_) return;
  max_scopes_ = std::max(scopes, 2 * max_scopes_);
  names_.clear();
  depths_.clear();
  create_pool();
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  names_.clear();
  depths_.clear();
  open_ = 0;
  if (pool_) vkCmdResetQueryPool(cmd, pool_, 0, 2 * max_scopes_);
}

uint32_t GpuTimer::begin(VkCommandBuffer cmd, const std::string& name) {
  ILLUM_CHECK(names_.size() < max_scopes_,
              "more than {} timer scopes in one frame: reserve() them first", max_scopes_);
  const uint32_t scope = static_cast<uint32_t>(names_.size());
  names_.push_back(name);
  depths_.push_back(open_++);
  if (pool_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, 2 * scope);
  return scope;
}

void GpuTimer::end(VkCommandBuffer cmd, uint32_t scope) {
  ILLUM_CHECK(open_ > 0 && scope < names_.size(), "timer scope ended twice");
  --open_;
  if (pool_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, 2 * scope + 1);
}

std::vector<PassTime> GpuTimer::resolve() const {
  std::vector<PassTime> out;
  if (!pool_ || names_.empty()) return out;
  std::vector<uint64_t> stamps(2 * names_.size());
  ILLUM_VK(vkGetQueryPoolResults(context_->device(), pool_, 0, static_cast<uint32_t>(stamps.size()),
                                 stamps.size() * sizeof(uint64_t), stamps.data(), sizeof(uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  for (size_t i = 0; i < names_.size(); ++i) {
    const double ticks = static_cast<double>(stamps[2 * i + 1] - stamps[2 * i]);
    out.push_back({names_[i], ticks * context_->timestamp_period_ns() * 1e-6, depths_[i]});
  }
  return out;
}

}  // namespace illum::gpu
