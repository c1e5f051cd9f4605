#include "illum/realtime/frame_globals.h"

#include <algorithm>

#include "illum/realtime/gpu_types.h"

namespace illum::realtime {

namespace {

using B = gpu::DescriptorBinding;
constexpr auto kUbo = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
constexpr auto kSsbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr auto kTexture = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
constexpr auto kReadOnly = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;

}  // namespace

FrameGlobals::FrameGlobals(gpu::Context& context, const GpuScene& scene, size_t light_count)
    : context_(context), descriptors_(context) {
  linear_ = gpu::Sampler(context, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_REPEAT, true);
  nearest_ = gpu::Sampler(context, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  clamp_linear_ = gpu::Sampler(context, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);

  gpu::ImageDesc small;
  small.format = VK_FORMAT_R32G32_SFLOAT;
  small.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  small.layers = 6;
  small.cube = true;
  small.cube_array = true;
  dummy_cube_ = gpu::GpuImage(context, small);
  small.layers = 1;
  small.cube = false;
  small.cube_array = false;
  dummy_2d_ = gpu::GpuImage(context, small);
  small.array = true;
  dummy_array_ = gpu::GpuImage(context, small);
  small.array = false;
  const Image far_moments(1, 1, 2, 1.0f);
  for (uint32_t l = 0; l < 6; ++l) dummy_cube_.upload(far_moments, l);
  dummy_2d_.upload(Image(1, 1, 2, 0.0f));
  dummy_array_.upload(far_moments);
  small.format = VK_FORMAT_R8G8B8A8_UNORM;
  dummy_white_ = gpu::GpuImage(context, small);
  dummy_white_.upload(Image(1, 1, 4, 1.0f));
  const std::vector<uint8_t> zeros(256, 0);
  dummy_buffer_ = gpu::make_device_buffer(context, zeros.data(), zeros.size(),
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);

  frame_ubo_ = gpu::Buffer(context, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                           gpu::MemoryUsage::kUpload);
  lights_ = gpu::Buffer(context, std::max<size_t>(1, light_count) * sizeof(GpuLight),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kUpload);

  layouts_.resize(kShadingSets);
  layouts_[kFrameSet] = gpu::DescriptorSetLayout(context, {B{0, kUbo}, B{1, kSsbo}, B{2, kSsbo}});
  layouts_[kMaterialSet] = gpu::DescriptorSetLayout(
      context, {B{0, kTexture}, B{1, kTexture}, B{2, kTexture}, B{3, kTexture}});
  layouts_[kPipelineSet] = gpu::DescriptorSetLayout(context, {});
  layouts_[kShadowSet] = gpu::DescriptorSetLayout(
      context,
      {B{0, kUbo}, B{1, kSsbo}, B{2, kTexture}, B{3, kTexture}, B{4, kTexture}, B{5, kSsbo}});
  layouts_[kBakedSet] =
      gpu::DescriptorSetLayout(context, {B{0, kUbo}, B{1, kTexture}, B{2, kSsbo}, B{3, kSsbo},
                                         B{4, kSsbo}, B{5, kSsbo}, B{6, kSsbo}});

  gpu::DescriptorWriter w;
  frame_set_ = descriptors_.allocate(layouts_[kFrameSet]);
  w.buffer(frame_set_, 0, kUbo, frame_ubo_.handle())
      .buffer(frame_set_, 1, kSsbo, scene.materials().handle())
      .buffer(frame_set_, 2, kSsbo, lights_.handle());
  const Scene& sc = scene.scene();
  auto texture_view = [&](int index) {
    return index >= 0 && static_cast<size_t>(index) < scene.textures().size()
               ? scene.textures()[static_cast<size_t>(index)].view()
               : dummy_white_.view();
  };
  for (size_t m = 0; m < std::max<size_t>(1, sc.materials.size()); ++m) {
    const VkDescriptorSet set = descriptors_.allocate(layouts_[kMaterialSet]);
    const Material mat = m < sc.materials.size() ? sc.materials[m] : Material{};
    w.image(set, 0, kTexture, texture_view(mat.albedo_texture), linear_.handle(), kReadOnly)
        .image(set, 1, kTexture, texture_view(mat.normal_texture), linear_.handle(), kReadOnly)
        .image(set, 2, kTexture, texture_view(mat.emission_texture), linear_.handle(), kReadOnly)
        .image(set, 3, kTexture, dummy_white_.view(), linear_.handle(), kReadOnly);
    material_sets_.push_back(set);
  }

  // Neutral sets: no shadow lookups (mode 0), no baked lighting (kind 0, no PRT, no probes).
  neutral_sets_.assign(kShadingSets, VK_NULL_HANDLE);
  neutral_sets_[kPipelineSet] = descriptors_.allocate(layouts_[kPipelineSet]);
  const ShadowUniforms no_shadows{};
  neutral_shadow_ubo_ = gpu::Buffer(context, sizeof(ShadowUniforms),
                                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::kUpload);
  neutral_shadow_ubo_.write(&no_shadows, sizeof(no_shadows));
  const VkDescriptorSet shadow = neutral_sets_[kShadowSet] =
      descriptors_.allocate(layouts_[kShadowSet]);
  w.buffer(shadow, 0, kUbo, neutral_shadow_ubo_.handle())
      .buffer(shadow, 1, kSsbo, dummy_buffer_.handle())
      .image(shadow, 2, kTexture, dummy_cube_.view(), nearest_.handle(), kReadOnly)
      .image(shadow, 3, kTexture, dummy_array_.view(), nearest_.handle(), kReadOnly)
      .image(shadow, 4, kTexture, dummy_array_.view(), nearest_.handle(), kReadOnly)
      .buffer(shadow, 5, kSsbo, dummy_buffer_.handle());
  const BakedUniforms no_baked{};
  neutral_baked_ubo_ = gpu::Buffer(context, sizeof(BakedUniforms),
                                   VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::kUpload);
  neutral_baked_ubo_.write(&no_baked, sizeof(no_baked));
  const VkDescriptorSet baked = neutral_sets_[kBakedSet] =
      descriptors_.allocate(layouts_[kBakedSet]);
  w.buffer(baked, 0, kUbo, neutral_baked_ubo_.handle())
      .image(baked, 1, kTexture, dummy_array_.view(), clamp_linear_.handle(), kReadOnly)
      .buffer(baked, 2, kSsbo, dummy_buffer_.handle())
      .buffer(baked, 3, kSsbo, dummy_buffer_.handle())
      .buffer(baked, 4, kSsbo, dummy_buffer_.handle())
      .buffer(baked, 5, kSsbo, dummy_buffer_.handle())
      .buffer(baked, 6, kSsbo, dummy_buffer_.handle());
  quad_counter_ =
      gpu::Buffer(context, 2 * sizeof(uint32_t),
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                      VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                  gpu::MemoryUsage::kDevice);
  quad_count_set_layout_ = gpu::DescriptorSetLayout(context, {B{0, kSsbo}});
  quad_count_set_ = descriptors_.allocate(quad_count_set_layout_);
  w.buffer(quad_count_set_, 0, kSsbo, quad_counter_.handle());
  w.commit(context.device());
  default_layout_ = shading_layout();
  quad_count_layout_ = shading_layout(quad_count_set_layout_.handle());
}

const gpu::DescriptorSetLayout& FrameGlobals::layout(uint32_t slot) const {
  return layouts_.at(slot);
}

VkDescriptorSet FrameGlobals::neutral_set(uint32_t slot) const {
  ILLUM_CHECK(slot >= kPipelineSet && slot < kShadingSets, "no neutral set at slot {}", slot);
  return neutral_sets_[slot];
}

int FrameGlobals::material_index(int material) const {
  return std::clamp(material, 0, static_cast<int>(material_sets_.size()) - 1);
}

VkDescriptorSet FrameGlobals::material_set(int material) const {
  return material_sets_[static_cast<size_t>(material_index(material))];
}

gpu::PipelineLayout FrameGlobals::shading_layout(VkDescriptorSetLayout pipeline_set) const {
  std::vector<VkDescriptorSetLayout> sets;
  for (uint32_t s = 0; s < kShadingSets; ++s) sets.push_back(layouts_[s].handle());
  if (pipeline_set != VK_NULL_HANDLE) sets[kPipelineSet] = pipeline_set;
  return gpu::PipelineLayout(context_, sets, sizeof(PushConstants));
}

void FrameGlobals::upload_lights(const std::vector<Light>& lights) {
  std::vector<GpuLight> gl;
  for (const Light& l : lights) {
    GpuLight g{};
    g.position_range = vec4(l.position, l.range);
    g.direction_cos = vec4(glm::normalize(l.direction), l.cos_cutoff());
    int type = 0;
    Color color = l.intensity;
    switch (l.type) {
      case LightType::kPoint:
        type = 0;
        break;
      case LightType::kSpot:
        type = l.cosine_falloff ? 3 : 1;
        break;
      case LightType::kDirectional:
        type = 2;
        color = l.irradiance;
        break;
      default:
        color = Color(0.0f);
        break;  // area/environment: not lit in real time
    }
    g.color_type = vec4(color, static_cast<float>(type));
    gl.push_back(g);
  }
  if (gl.empty()) gl.push_back(GpuLight{});
  lights_.write(gl.data(), gl.size() * sizeof(GpuLight));
}

void FrameGlobals::update(const FrameView& view, const RenderSettings& s, size_t light_count,
                          uint32_t width, uint32_t height) {
  FrameUniforms u{};
  u.view = view.view;
  u.proj = view.proj;
  u.view_proj = view.view_proj;
  u.inv_view_proj = view.inv_view_proj;
  u.camera_pos = vec4(view.camera.position, 0.0f);
  u.ambient = vec4(s.get<Color>("lighting.ambient"), 0.0f);
  u.counts = glm::ivec4(static_cast<int>(light_count), s.get<bool>("lighting.half_lambert") ? 1 : 0,
                        s.get<int>("lighting.single_light"), 0);
  u.extent = vec4(static_cast<float>(width), static_cast<float>(height),
                  1.0f / static_cast<float>(width), 1.0f / static_cast<float>(height));
  frame_ubo_.write(&u, sizeof(u));
}

void bind_shading_sets(VkCommandBuffer cmd, VkPipelineBindPoint point, VkPipelineLayout layout,
                       const FrameGlobals& globals, const std::array<VkDescriptorSet, 3>& sets) {
  const VkDescriptorSet all[kShadingSets] = {globals.frame_set(), globals.material_set(0), sets[0],
                                             sets[1], sets[2]};
  vkCmdBindDescriptorSets(cmd, point, layout, 0, kShadingSets, all, 0, nullptr);
}

}  // namespace illum::realtime
