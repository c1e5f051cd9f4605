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
  // Depth 2: a depth of 1 is a 2-D image (gpu_image.h).
  small.depth = 2;
  dummy_3d_ = gpu::GpuImage(context, small);
  small.depth = 1;
  const Image far_moments(1, 1, 2, 1.0f);
  for (uint32_t l = 0; l < 6; ++l) dummy_cube_.upload(far_moments, l);
  dummy_2d_.upload(Image(1, 1, 2, 0.0f));
  // upload() fills 2-D images only: the 3-D dummy is cleared.
  context.immediate([&](VkCommandBuffer c) {
    dummy_3d_.transition(c, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                         VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkClearColorValue zero{};
    const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(c, dummy_3d_.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1,
                         &all);
    dummy_3d_.transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                         VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  });
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
  // Zeroed, so a view no technique wrote is a degenerate camera, not garbage.
  const std::vector<GpuView> no_views(kMaxViews, GpuView{});
  views_ = gpu::Buffer(context, kMaxViews * sizeof(GpuView), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       gpu::MemoryUsage::kUpload);
  views_.write(no_views.data(), kMaxViews * sizeof(GpuView));
  view_used_.assign(kMaxViews, false);
  view_used_[0] = true;  // the frame's camera

  layouts_.resize(kShadingSets);
  layouts_[kFrameSet] =
      gpu::DescriptorSetLayout(context, {B{0, kUbo}, B{1, kSsbo}, B{2, kSsbo}, B{3, kSsbo}});
  layouts_[kMaterialSet] = gpu::DescriptorSetLayout(
      context, {B{0, kTexture}, B{1, kTexture}, B{2, kTexture}, B{3, kTexture}});
  layouts_[kPipelineSet] = gpu::DescriptorSetLayout(context, {});
  layouts_[kShadowSet] = gpu::DescriptorSetLayout(
      context,
      {B{0, kUbo}, B{1, kSsbo}, B{2, kTexture}, B{3, kTexture}, B{4, kTexture}, B{5, kSsbo}});
  layouts_[kInputsSet] = gpu::DescriptorSetLayout(context, lighting_inputs_layout());

  gpu::DescriptorWriter w;
  frame_set_ = descriptors_.allocate(layouts_[kFrameSet]);
  w.buffer(frame_set_, 0, kUbo, frame_ubo_.handle())
      .buffer(frame_set_, 1, kSsbo, scene.materials().handle())
      .buffer(frame_set_, 2, kSsbo, lights_.handle())
      .buffer(frame_set_, 3, kSsbo, views_.handle());
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

  // Neutral sets: no shadow lookups (mode 0), no lighting input active.
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
  neutral_inputs_ = make_lighting_inputs_zeros(context);
  neutral_sets_[kInputsSet] = descriptors_.allocate(layouts_[kInputsSet]);
  write_neutral_lighting_inputs(w, neutral_sets_[kInputsSet], *this, neutral_inputs_.handle());
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
  write_view(0, view, {width, height});
}

namespace {
const vec3 kCubeAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const vec3 kCubeUps[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
}  // namespace

vec3 cube_face_axis(int face) {
  return kCubeAxes[face];
}

mat4 cube_face_view(const vec3& eye, int face) {
  return glm::lookAtRH(eye, eye + kCubeAxes[face], kCubeUps[face]);
}

FrameView light_view(const mat4& view, const mat4& proj, const vec3& eye, float near_plane,
                     float far_plane) {
  FrameView v;
  v.camera.position = eye;
  v.view = view;
  v.proj = proj;
  v.view_proj = proj * view;
  v.inv_view_proj = glm::inverse(v.view_proj);
  v.near_plane = near_plane;
  v.far_plane = far_plane;
  return v;
}

FrameView camera_view(const Camera& camera, const Bounds3& b, uint32_t width, uint32_t height) {
  FrameView view;
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float dist = glm::length(camera.position - b.center());
  view.far_plane = std::max(dist + b.diagonal(), 1e-3f) * 1.01f;
  // 1e-3: float depth then resolves ~1e-4 of the distance at 2 m in a 4 m scene, well
  // below the shadow-volume cap offset.
  view.near_plane = view.far_plane * 1e-3f;
  view.aspect = aspect;
  view.camera = camera;
  view.view = camera.view_matrix();
  view.proj = camera.projection_matrix(aspect, view.near_plane, view.far_plane);
  view.view_proj = view.proj * view.view;
  view.inv_view_proj = glm::inverse(view.view_proj);
  return view;
}

ViewSlots FrameGlobals::add_views(uint32_t count) {
  uint32_t run = 0;
  for (uint32_t i = 0; i < kMaxViews && count > 0; ++i) {
    run = view_used_[i] ? 0 : run + 1;
    if (run < count) continue;
    ViewSlots slots;
    slots.owner_ = this;
    slots.first_ = i + 1 - count;
    slots.count_ = count;
    for (uint32_t k = slots.first_; k <= i; ++k) view_used_[k] = true;
    return slots;
  }
  if (count == 0) return ViewSlots();
  const auto used = std::count(view_used_.begin(), view_used_.end(), true);
  throw Error(fmt::format("the camera block has no room for {} more views ({} of {} in use)", count,
                          used, kMaxViews));
}

void FrameGlobals::set_view(uint32_t index, const FrameView& view, VkExtent2D extent) {
  ILLUM_CHECK(index > 0 && index < kMaxViews && view_used_[index],
              "view {} of the camera block was not added", index);
  write_view(index, view, extent);
}

void FrameGlobals::write_view(uint32_t index, const FrameView& view, VkExtent2D extent) {
  GpuView v{};
  v.view = view.view;
  v.proj = view.proj;
  v.view_proj = view.view_proj;
  v.inv_view_proj = view.inv_view_proj;
  v.camera_pos = vec4(view.camera.position, 0.0f);
  const float w = static_cast<float>(extent.width), h = static_cast<float>(extent.height);
  v.extent = vec4(w, h, 1.0f / w, 1.0f / h);
  v.planes = vec4(view.near_plane, view.far_plane, 0.0f, 0.0f);
  views_.write(&v, sizeof(v), index * sizeof(GpuView));
}

ViewSlots& ViewSlots::operator=(ViewSlots&& o) noexcept {
  if (this != &o) {
    release();
    owner_ = std::exchange(o.owner_, nullptr);
    first_ = o.first_;
    count_ = std::exchange(o.count_, 0);
  }
  return *this;
}

uint32_t ViewSlots::operator[](uint32_t k) const {
  ILLUM_CHECK(k < count_, "view slot {} of {}", k, count_);
  return first_ + k;
}

void ViewSlots::release() {
  if (!owner_) return;
  for (uint32_t k = 0; k < count_; ++k) owner_->view_used_[first_ + k] = false;
  owner_ = nullptr;
  count_ = 0;
}

void bind_shading_sets(VkCommandBuffer cmd, VkPipelineBindPoint point, VkPipelineLayout layout,
                       const FrameGlobals& globals, const std::array<VkDescriptorSet, 3>& sets) {
  const VkDescriptorSet all[kShadingSets] = {globals.frame_set(), globals.material_set(0), sets[0],
                                             sets[1], sets[2]};
  vkCmdBindDescriptorSets(cmd, point, layout, 0, kShadingSets, all, 0, nullptr);
}

}  // namespace illum::realtime
