#include "illum/gpu/pipeline.h"

#include <utility>

#include "illum/gpu/shader_library.h"
#include "illum/gpu/vk_check.h"

namespace illum::gpu {

VkShaderModule create_shader_module(Context& context, const std::string& name) {
  const auto words = shader_spirv(name);
  if (words.empty()) throw Error(fmt::format("shader '{}' is not embedded in this build", name));
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = words.size_bytes();
  info.pCode = words.data();
  VkShaderModule module = VK_NULL_HANDLE;
  const VkResult r = vkCreateShaderModule(context.device(), &info, nullptr, &module);
  if (r != VK_SUCCESS)
    throw Error(fmt::format("shader '{}': module creation failed ({})", name, to_string(r)));
  return module;
}

PipelineLayout::PipelineLayout(Context& context, const std::vector<VkDescriptorSetLayout>& sets,
                               uint32_t push_constant_bytes)
    : context_(&context) {
  VkPushConstantRange range{VK_SHADER_STAGE_ALL, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = static_cast<uint32_t>(sets.size());
  info.pSetLayouts = sets.data();
  info.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
  info.pPushConstantRanges = &range;
  ILLUM_VK(vkCreatePipelineLayout(context.device(), &info, nullptr, &layout_));
}

PipelineLayout& PipelineLayout::operator=(PipelineLayout&& o) noexcept {
  if (this != &o) {
    reset();
    context_ = std::exchange(o.context_, nullptr);
    layout_ = std::exchange(o.layout_, VK_NULL_HANDLE);
  }
  return *this;
}

void PipelineLayout::reset() {
  if (context_ && layout_) vkDestroyPipelineLayout(context_->device(), layout_, nullptr);
  layout_ = VK_NULL_HANDLE;
  context_ = nullptr;
}

namespace {
struct Modules {
  VkDevice device;
  std::vector<VkShaderModule> list;
  ~Modules() {
    for (VkShaderModule m : list) vkDestroyShaderModule(device, m, nullptr);
  }
};
}  // namespace

Pipeline::Pipeline(Context& context, VkPipelineLayout layout, const GraphicsPipelineDesc& d)
    : context_(&context), vertex_stride_(d.vertex_input.stride) {
  Modules modules{context.device(), {}};
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  modules.list.push_back(create_shader_module(context, d.vertex_shader));
  stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                    VK_SHADER_STAGE_VERTEX_BIT, modules.list.back(), "main", nullptr});
  if (!d.fragment_shader.empty()) {
    modules.list.push_back(create_shader_module(context, d.fragment_shader));
    stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                      VK_SHADER_STAGE_FRAGMENT_BIT, modules.list.back(), "main",
                      d.fragment_specialization});
  }
  VkVertexInputBindingDescription binding{0, d.vertex_input.stride, VK_VERTEX_INPUT_RATE_VERTEX};
  VkPipelineVertexInputStateCreateInfo vertex{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  if (d.vertex_input.stride) {
    vertex.vertexBindingDescriptionCount = 1;
    vertex.pVertexBindingDescriptions = &binding;
    vertex.vertexAttributeDescriptionCount =
        static_cast<uint32_t>(d.vertex_input.attributes.size());
    vertex.pVertexAttributeDescriptions = d.vertex_input.attributes.data();
  }
  VkPipelineInputAssemblyStateCreateInfo assembly{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = d.topology;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = d.cull;
  raster.frontFace = d.front_face;
  raster.lineWidth = 1.0f;
  raster.depthClampEnable = d.depth_clamp ? VK_TRUE : VK_FALSE;
  raster.depthBiasEnable = d.depth_bias ? VK_TRUE : VK_FALSE;
  VkPipelineMultisampleStateCreateInfo multisample{
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = d.depth_test ? VK_TRUE : VK_FALSE;
  depth.depthWriteEnable = d.depth_write ? VK_TRUE : VK_FALSE;
  depth.depthCompareOp = d.depth_compare;
  depth.stencilTestEnable = d.stencil_test ? VK_TRUE : VK_FALSE;
  depth.front = d.stencil_front;
  depth.back = d.stencil_back;
  depth.maxDepthBounds = 1.0f;
  std::vector<VkPipelineColorBlendAttachmentState> blends(d.color_formats.size());
  for (auto& b : blends) {
    b = {};
    b.colorWriteMask = d.color_write ? (VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                        VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT)
                                     : 0;
    if (d.additive_blend) {
      b.blendEnable = VK_TRUE;
      b.srcColorBlendFactor = b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
      b.srcAlphaBlendFactor = b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      b.colorBlendOp = b.alphaBlendOp = VK_BLEND_OP_ADD;
    }
  }
  VkPipelineColorBlendStateCreateInfo blend{
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = static_cast<uint32_t>(blends.size());
  blend.pAttachments = blends.data();
  std::vector<VkDynamicState> dynamic = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  if (d.depth_bias) dynamic.push_back(VK_DYNAMIC_STATE_DEPTH_BIAS);
  if (d.stencil_test) dynamic.push_back(VK_DYNAMIC_STATE_STENCIL_REFERENCE);
  VkPipelineDynamicStateCreateInfo dyn{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dyn.dynamicStateCount = static_cast<uint32_t>(dynamic.size());
  dyn.pDynamicStates = dynamic.data();
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = static_cast<uint32_t>(d.color_formats.size());
  rendering.pColorAttachmentFormats = d.color_formats.data();
  rendering.depthAttachmentFormat = d.depth_format;
  rendering.stencilAttachmentFormat = d.stencil_format;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.pNext = &rendering;
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.pVertexInputState = &vertex;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dyn;
  info.layout = layout;
  const VkResult r =
      vkCreateGraphicsPipelines(context.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  if (r != VK_SUCCESS)
    throw Error(fmt::format("pipeline '{}'+'{}' creation failed ({})", d.vertex_shader,
                            d.fragment_shader, to_string(r)));
}

Pipeline::Pipeline(Context& context, VkPipelineLayout layout, const std::string& compute_shader)
    : context_(&context) {
  Modules modules{context.device(), {create_shader_module(context, compute_shader)}};
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                nullptr,
                0,
                VK_SHADER_STAGE_COMPUTE_BIT,
                modules.list[0],
                "main",
                nullptr};
  info.layout = layout;
  const VkResult r =
      vkCreateComputePipelines(context.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  if (r != VK_SUCCESS)
    throw Error(
        fmt::format("compute pipeline '{}' creation failed ({})", compute_shader, to_string(r)));
}

Pipeline& Pipeline::operator=(Pipeline&& o) noexcept {
  if (this != &o) {
    reset();
    context_ = std::exchange(o.context_, nullptr);
    pipeline_ = std::exchange(o.pipeline_, VK_NULL_HANDLE);
    vertex_stride_ = std::exchange(o.vertex_stride_, 0);
  }
  return *this;
}

void Pipeline::reset() {
  if (context_ && pipeline_) vkDestroyPipeline(context_->device(), pipeline_, nullptr);
  pipeline_ = VK_NULL_HANDLE;
  context_ = nullptr;
}

}  // namespace illum::gpu
