#include "illum/gpu/gpu_timer.h"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "illum/gpu/gpu_image.h"
#include "illum/gpu/vk_check.h"

namespace illum::gpu {

std::string RasterFill::key() const {
  std::vector<std::string> formats;
  for (VkFormat c : colors) formats.emplace_back(format_name(c));
  if (depth != Depth::kNone) formats.emplace_back(format_name(depth_format));
  const char* how = depth == Depth::kWrite          ? " write"
                    : depth == Depth::kTest         ? " test"
                    : depth == Depth::kStencil      ? " stencil"
                    : depth == Depth::kStencilTest  ? " stencil-test"
                    : depth == Depth::kReject       ? " reject"
                    : depth == Depth::kStencilZFail ? " zfail"
                                                    : "";
  std::string kept;
  for (size_t i = 0; i < colors.size(); ++i)
    if (uncleared & (1u << i)) kept += std::to_string(i);
  return fmt::format(
      "{}x{} {}{}{}{}", width, height,
      formats.empty() ? std::string("none") : fmt::format("{}", fmt::join(formats, "+")), how,
      blend ? " blend" : "", kept.empty() ? "" : " uncleared:" + kept);
}

GpuTimer::GpuTimer(Context& context, uint32_t max_scopes)
    : context_(&context), max_scopes_(max_scopes) {
  create_pool();
}

GpuTimer::~GpuTimer() {
  if (pool_) vkDestroyQueryPool(context_->device(), pool_, nullptr);
  if (occlusion_) vkDestroyQueryPool(context_->device(), occlusion_, nullptr);
  if (statistics_) vkDestroyQueryPool(context_->device(), statistics_, nullptr);
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
  stack_.clear();
  fills_.clear();
  bytes_.clear();
  triangles_.clear();
  clusters_.clear();
  drawn_scopes_.clear();
  counts_.clear();
  rasterized_scopes_.clear();
  quad_scopes_.clear();
  open_ = 0;
  if (pool_) vkCmdResetQueryPool(cmd, pool_, 0, 2 * max_scopes_);
  if (counting_ && occlusion_) vkCmdResetQueryPool(cmd, occlusion_, 0, occlusion_capacity_);
  if (counting_ && statistics_) vkCmdResetQueryPool(cmd, statistics_, 0, occlusion_capacity_);
}

uint32_t GpuTimer::begin(VkCommandBuffer cmd, const std::string& name) {
  ILLUM_CHECK(names_.size() < max_scopes_,
              "more than {} timer scopes in one frame: reserve() them first", max_scopes_);
  const uint32_t scope = static_cast<uint32_t>(names_.size());
  names_.push_back(name);
  depths_.push_back(open_++);
  fills_.emplace_back();
  bytes_.push_back(0.0);
  triangles_.push_back(0.0);
  clusters_.push_back(-1.0);
  stack_.push_back(scope);
  if (pool_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, 2 * scope);
  return scope;
}

void GpuTimer::end(VkCommandBuffer cmd, uint32_t scope) {
  ILLUM_CHECK(open_ > 0 && scope < names_.size() && !stack_.empty() && stack_.back() == scope,
              "timer scope ended twice or out of order");
  --open_;
  stack_.pop_back();
  if (pool_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, 2 * scope + 1);
}

void GpuTimer::note_fill(const RasterFill& fill, double count) {
  if (!stack_.empty()) fills_[stack_.back()].emplace_back(fill, count);
}

void GpuTimer::note_bytes(double bytes) {
  if (!stack_.empty()) bytes_[stack_.back()] += bytes;
}

void GpuTimer::note_triangles(double triangles) {
  if (!stack_.empty()) triangles_[stack_.back()] += triangles;
}

void GpuTimer::note_clusters(double clusters) {
  if (!stack_.empty())
    clusters_[stack_.back()] = std::max(0.0, clusters_[stack_.back()]) + clusters;
}

void GpuTimer::note_drawn(VkCommandBuffer cmd, VkBuffer counter, VkDeviceSize offset) {
  if (stack_.empty() || !pool_) return;
  constexpr uint32_t kCapacity = 1024;  // notes a frame: one per culled view
  ILLUM_CHECK(drawn_scopes_.size() < kCapacity, "more than {} GPU-counted views in one frame",
              kCapacity);
  if (!drawn_readback_)
    drawn_readback_ = Buffer(*context_, kCapacity * 2 * sizeof(uint32_t),
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::kReadback);
  const VkDeviceSize bytes = 2 * sizeof(uint32_t);
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  const VkBufferCopy region{offset, drawn_scopes_.size() * bytes, bytes};
  vkCmdCopyBuffer(cmd, counter, drawn_readback_.handle(), 1, &region);
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  drawn_scopes_.push_back(stack_.back());
}

void GpuTimer::set_counting(bool on, bool statistics) {
  counting_ = on;
  statistics_on_ = statistics;
  if (!on || occlusion_) return;
  occlusion_capacity_ = 256;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_OCCLUSION;
  info.queryCount = occlusion_capacity_;
  ILLUM_VK(vkCreateQueryPool(context_->device(), &info, nullptr, &occlusion_));
  if (context_->quad_counting())
    quad_readback_ = Buffer(*context_, occlusion_capacity_ * 2 * sizeof(uint32_t),
                            VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::kReadback);
  if (!context_->pipeline_statistics()) return;
  info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
  // Results come in bit order: vertex shader invocations, then clipping output.
  info.pipelineStatistics = VK_QUERY_PIPELINE_STATISTIC_VERTEX_SHADER_INVOCATIONS_BIT |
                            VK_QUERY_PIPELINE_STATISTIC_CLIPPING_PRIMITIVES_BIT;
  ILLUM_VK(vkCreateQueryPool(context_->device(), &info, nullptr, &statistics_));
}

uint32_t GpuTimer::begin_rasterized(VkCommandBuffer cmd) {
  if (!counting() || !statistics_ || !statistics_on_) return ~0u;
  ILLUM_CHECK(rasterized_scopes_.size() < occlusion_capacity_,
              "more than {} counted draws in one frame", occlusion_capacity_);
  const uint32_t query = static_cast<uint32_t>(rasterized_scopes_.size());
  rasterized_scopes_.push_back(stack_.empty() ? ~0u : stack_.back());
  vkCmdBeginQuery(cmd, statistics_, query, 0);
  return query;
}

void GpuTimer::end_rasterized(VkCommandBuffer cmd, uint32_t query) {
  if (query == ~0u) return;
  ILLUM_CHECK(query < rasterized_scopes_.size(), "end_rasterized without begin_rasterized");
  vkCmdEndQuery(cmd, statistics_, query);
}

uint32_t GpuTimer::begin_count(VkCommandBuffer cmd) {
  if (!counting()) return 0;
  ILLUM_CHECK(counts_.size() < occlusion_capacity_, "more than {} counted draws in one frame",
              occlusion_capacity_);
  const uint32_t query = static_cast<uint32_t>(counts_.size());
  counts_.push_back({stack_.empty() ? ~0u : stack_.back(), {}});
  vkCmdBeginQuery(cmd, occlusion_, query,
                  context_->occlusion_query_precise() ? VK_QUERY_CONTROL_PRECISE_BIT : 0);
  return query;
}

void GpuTimer::end_count(VkCommandBuffer cmd, uint32_t query, const RasterFill& per_sample,
                         int minus) {
  if (!counting()) return;
  ILLUM_CHECK(query < counts_.size() && minus < static_cast<int>(query),
              "end_count without begin_count");
  counts_[query].fill = per_sample;
  counts_[query].minus = minus;
  vkCmdEndQuery(cmd, occlusion_, query);
}

void GpuTimer::begin_quads(VkCommandBuffer cmd, VkBuffer counter) {
  if (!counts_quads()) return;
  vkCmdFillBuffer(cmd, counter, 0, 2 * sizeof(uint32_t), 0);
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void GpuTimer::end_quads(VkCommandBuffer cmd, VkBuffer counter) {
  if (!counts_quads()) return;
  ILLUM_CHECK(quad_scopes_.size() < occlusion_capacity_,
              "more than {} quad-counted renderings in one frame", occlusion_capacity_);
  const VkDeviceSize bytes = 2 * sizeof(uint32_t);
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  const VkBufferCopy region{0, quad_scopes_.size() * bytes, bytes};
  vkCmdCopyBuffer(cmd, counter, quad_readback_.handle(), 1, &region);
  // The next begin_quads() overwrites the counter; the host reads the copy after the fence.
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                 VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_READ_BIT);
  quad_scopes_.push_back(stack_.empty() ? ~0u : stack_.back());
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
    out.push_back({names_[i], ticks * context_->timestamp_period_ns() * 1e-6, depths_[i], fills_[i],
                   bytes_[i], triangles_[i]});
    out.back().clusters = clusters_[i];
  }
  if (!drawn_scopes_.empty()) {
    std::vector<uint32_t> counts(2 * drawn_scopes_.size());
    drawn_readback_.read(counts.data(), counts.size() * sizeof(uint32_t));
    for (size_t q = 0; q < drawn_scopes_.size(); ++q) {
      const uint32_t scope = drawn_scopes_[q];
      if (scope >= out.size()) continue;
      out[scope].triangles += counts[2 * q];
      out[scope].clusters = std::max(0.0, out[scope].clusters) + counts[2 * q + 1];
    }
  }
  if (counting() && !counts_.empty()) {
    std::vector<uint64_t> samples(counts_.size());
    ILLUM_VK(vkGetQueryPoolResults(
        context_->device(), occlusion_, 0, static_cast<uint32_t>(samples.size()),
        samples.size() * sizeof(uint64_t), samples.data(), sizeof(uint64_t),
        VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (size_t q = 0; q < counts_.size(); ++q) {
      const Count& c = counts_[q];
      if (c.scope >= out.size()) continue;
      const double area = static_cast<double>(c.fill.width) * c.fill.height;
      const double less = c.minus >= 0 ? static_cast<double>(samples[c.minus]) : 0.0;
      const double n = std::max(0.0, static_cast<double>(samples[q]) - less);
      out[c.scope].fills.emplace_back(c.fill, area > 0.0 ? n / area : 0.0);
    }
  }
  if (counting() && !rasterized_scopes_.empty()) {
    const size_t n = rasterized_scopes_.size();
    std::vector<uint64_t> stats(2 * n);  // per query: vertex invocations, clipping output
    ILLUM_VK(vkGetQueryPoolResults(context_->device(), statistics_, 0, static_cast<uint32_t>(n),
                                   stats.size() * sizeof(uint64_t), stats.data(),
                                   2 * sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (size_t q = 0; q < n; ++q) {
      const uint32_t scope = rasterized_scopes_[q];
      if (scope >= out.size()) continue;
      out[scope].vertices = std::max(0.0, out[scope].vertices) + static_cast<double>(stats[2 * q]);
      out[scope].rasterized =
          std::max(0.0, out[scope].rasterized) + static_cast<double>(stats[2 * q + 1]);
    }
  }
  if (counts_quads() && !quad_scopes_.empty()) {
    std::vector<uint32_t> counts(2 * quad_scopes_.size());
    quad_readback_.read(counts.data(), counts.size() * sizeof(uint32_t));
    for (size_t q = 0; q < quad_scopes_.size(); ++q) {
      const uint32_t scope = quad_scopes_[q];
      if (scope >= out.size()) continue;
      out[scope].quads = std::max(0.0, out[scope].quads) + counts[2 * q];
      out[scope].quad_samples = std::max(0.0, out[scope].quad_samples) + counts[2 * q + 1];
    }
  }
  return out;
}

}  // namespace illum::gpu
