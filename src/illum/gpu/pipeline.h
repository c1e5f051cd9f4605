// Pipelines from embedded SPIR-V: graphics pipelines for dynamic rendering (attachment
// formats instead of render passes) and compute pipelines. Viewport and scissor are
// dynamic. A shader or pipeline creation failure throws illum::Error naming the shader.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/context.h"

namespace illum::gpu {

class PipelineLayout {
 public:
  PipelineLayout() = default;
  PipelineLayout(Context& context, const std::vector<VkDescriptorSetLayout>& sets,
                 uint32_t push_constant_bytes);
  ~PipelineLayout() { reset(); }
  PipelineLayout(PipelineLayout&& o) noexcept { *this = std::move(o); }
  PipelineLayout& operator=(PipelineLayout&& o) noexcept;
  PipelineLayout(const PipelineLayout&) = delete;
  PipelineLayout& operator=(const PipelineLayout&) = delete;
  VkPipelineLayout handle() const { return layout_; }
  void reset();

 private:
  Context* context_ = nullptr;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
};

struct VertexInput {
  uint32_t stride = 0;  // 0 = no vertex buffer (full-screen passes)
  std::vector<VkVertexInputAttributeDescription> attributes;
};

struct GraphicsPipelineDesc {
  std::string vertex_shader;    // embedded names, e.g. "forward.vert"
  std::string fragment_shader;  // "" = depth/stencil only
  VertexInput vertex_input;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkCullModeFlags cull = VK_CULL_MODE_BACK_BIT;
  VkFrontFace front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  bool depth_test = true;
  bool depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_LESS;
  bool depth_clamp = false;
  bool depth_bias = false;  // dynamic state when on
  bool stencil_test = false;
  VkStencilOpState stencil_front{}, stencil_back{};
  std::vector<VkFormat> color_formats;
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  VkFormat stencil_format = VK_FORMAT_UNDEFINED;
  bool additive_blend = false;  // ONE + ONE on every colour attachment
  bool color_write = true;
  VkSpecializationInfo* fragment_specialization = nullptr;
};

class Pipeline {
 public:
  Pipeline() = default;
  Pipeline(Context& context, VkPipelineLayout layout, const GraphicsPipelineDesc& desc);
  // Compute pipeline.
  Pipeline(Context& context, VkPipelineLayout layout, const std::string& compute_shader);
  ~Pipeline() { reset(); }
  Pipeline(Pipeline&& o) noexcept { *this = std::move(o); }
  Pipeline& operator=(Pipeline&& o) noexcept;
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;
  VkPipeline handle() const { return pipeline_; }
  explicit operator bool() const { return pipeline_ != VK_NULL_HANDLE; }
  // The vertex buffer stride it was built for (0: none, or a compute pipeline), so a drawer
  // binds the vertex stream that layout reads.
  uint32_t vertex_stride() const { return vertex_stride_; }
  void reset();

 private:
  Context* context_ = nullptr;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  uint32_t vertex_stride_ = 0;
};

// A shader module from the embedded SPIR-V; throws Error when `name` is not embedded or
// the driver rejects it. The caller destroys the module.
VkShaderModule create_shader_module(Context& context, const std::string& name);

}  // namespace illum::gpu
