#include "illum/realtime/stencil_shadows.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "illum/core/log.h"
#include "illum/gpu/vk_check.h"
#include "illum/realtime/gpu_types.h"
#include "illum/realtime/realtime_lights.h"

namespace illum::realtime {

namespace {

// shaders/silhouettes.comp's VolumeTriangle.
struct GpuVolumeTriangle {
  glm::vec4 p[3];        // p[0].w: 1 = open mesh
  glm::ivec4 neighbour;  // w: bit k = same direction across edge k
};
static_assert(sizeof(GpuVolumeTriangle) == 64);

struct ExtractionPush {
  glm::vec4 position_range;
  glm::vec4 direction_type;
  glm::vec4 params;   // cone half-angle, cap offset, back-facing casters
  glm::uvec4 counts;  // triangles, light slot
};

constexpr uint32_t kExtractionGroup = 64;  // silhouettes.comp's local_size_x
// A caster emits two caps and at most three side quads.
constexpr VkDeviceSize kMaxVerticesPerTriangle = 6 + 3 * 6;

}  // namespace

VkDeviceSize gpu_volume_bytes(size_t triangles, const VkPhysicalDeviceLimits& limits,
                              const std::string& device) {
  const VkDeviceSize bytes =
      std::max<VkDeviceSize>(1, triangles * kMaxVerticesPerTriangle) * sizeof(glm::vec4);
  const VkDeviceSize groups = (triangles + kExtractionGroup - 1) / kExtractionGroup;
  if (bytes > limits.maxStorageBufferRange || groups > limits.maxComputeWorkGroupCount[0])
    throw Error(fmt::format(
        "silhouettes=gpu: {} caster triangles need {} MiB of volume vertices per light, more "
        "than one storage buffer of '{}' holds ({} MiB) or one dispatch reaches; use -p "
        "silhouettes=cpu",
        triangles, (bytes + (1 << 20) - 1) >> 20, device, limits.maxStorageBufferRange >> 20));
  return bytes;
}

VkStencilOpState stencil_op(VkStencilOp pass, VkStencilOp depth_fail, VkCompareOp compare,
                            uint32_t write_mask) {
  return {VK_STENCIL_OP_KEEP, pass, depth_fail, compare, 0xff, write_mask, 0};
}

void use_z_fail_count(gpu::GraphicsPipelineDesc* d) {
  d->cull = VK_CULL_MODE_NONE;
  d->depth_write = false;
  d->stencil_test = true;
  d->stencil_front =
      stencil_op(VK_STENCIL_OP_KEEP, VK_STENCIL_OP_DECREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS);
  d->stencil_back =
      stencil_op(VK_STENCIL_OP_KEEP, VK_STENCIL_OP_INCREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS);
}

void use_stencil_zero_test(gpu::GraphicsPipelineDesc* d) {
  d->stencil_test = true;
  d->stencil_front =
      stencil_op(VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_EQUAL, /*write_mask=*/0);
  d->stencil_back = d->stencil_front;
}

VkRect2D light_scissor(const Light& l, const Bounds3& b, const mat4& view_proj, uint32_t width,
                       uint32_t height) {
  const VkRect2D full{{0, 0}, {width, height}};
  if (l.type != LightType::kSpot || l.cone_half_angle >= radians(80.0f)) return full;
  float reach = 0.0f;
  for (int k = 0; k < 8; ++k) {
    const vec3 corner(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y,
                      k & 4 ? b.max.z : b.min.z);
    reach = std::max(reach, glm::length(corner - l.position));
  }
  if (l.range > 0.0f) reach = std::min(reach, l.range);
  const vec3 dir = glm::normalize(l.direction);
  const vec3 u =
      glm::normalize(glm::cross(std::abs(dir.y) < 0.99f ? vec3(0, 1, 0) : vec3(1, 0, 0), dir));
  const vec3 w = glm::cross(dir, u);
  const float half = reach * std::tan(l.cone_half_angle) * 1.01f;
  const vec3 points[5] = {l.position, l.position + dir * reach + (u + w) * half,
                          l.position + dir * reach + (u - w) * half,
                          l.position + dir * reach - (u + w) * half,
                          l.position + dir * reach - (u - w) * half};
  vec2 lo(1e30f), hi(-1e30f);
  for (const vec3& p : points) {
    const vec4 h = view_proj * vec4(p, 1.0f);
    if (h.w <= 1e-6f) return full;
    const vec2 ndc = vec2(h) / h.w;
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
  }
  const vec2 size(static_cast<float>(width), static_cast<float>(height));
  const vec2 p0 = glm::clamp(glm::floor((lo * 0.5f + 0.5f) * size) - 1.0f, vec2(0.0f), size);
  const vec2 p1 = glm::clamp(glm::ceil((hi * 0.5f + 0.5f) * size) + 1.0f, vec2(0.0f), size);
  if (p1.x <= p0.x || p1.y <= p0.y) return {{0, 0}, {1, 1}};  // the cone is off screen
  return {{static_cast<int32_t>(p0.x), static_cast<int32_t>(p0.y)},
          {static_cast<uint32_t>(p1.x - p0.x), static_cast<uint32_t>(p1.y - p0.y)}};
}

StencilShadows::StencilShadows(gpu::Context& context, const GpuScene& scene, size_t light_count,
                               SilhouetteSource source, VkPipelineLayout pipeline_layout,
                               VkFormat color_format, VkFormat depth_format)
    : context_(context),
      source_(source),
      builder_(scene.scene()),
      // Front caps sit this far behind their casters, beyond the depth buffer's
      // resolution, so a lit caster never fights with its own cap.
      cap_offset_(scene.bounds().diagonal() * 2e-3f),
      pipeline_layout_(pipeline_layout) {
  gpu::GraphicsPipelineDesc v;
  v.vertex_shader = "shadow_volume.vert";
  v.vertex_input.stride = sizeof(glm::vec4);
  v.vertex_input.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
  v.depth_compare = VK_COMPARE_OP_LESS;
  v.depth_clamp = true;  // the back cap lies at infinity
  use_z_fail_count(&v);
  v.color_formats = {color_format};
  v.color_write = false;
  v.depth_format = depth_format;
  v.stencil_format = depth_format;
  stencil_pipeline_ = gpu::Pipeline(context, pipeline_layout, v);
  // Counting frames (Renderer::measure_work): the same draws with no test at all, so an
  // occlusion query counts every sample the z-fail pass rasterizes (each costs a stencil
  // update or a depth test), i.e. the volumes' overdraw.
  gpu::GraphicsPipelineDesc counted = v;
  counted.depth_test = false;
  counted.depth_write = false;
  counted.stencil_test = false;
  count_pipeline_ = gpu::Pipeline(context, pipeline_layout, counted);

  if (source == SilhouetteSource::kGpu) create_gpu_resources(light_count);
}

StencilShadows::~StencilShadows() = default;

void StencilShadows::create_gpu_resources(size_t light_count) {
  const auto& tris = builder_.triangles();
  std::vector<GpuVolumeTriangle> data;
  data.reserve(tris.size());
  for (const ShadowVolumeBuilder::Triangle& t : tris) {
    GpuVolumeTriangle g;
    for (int k = 0; k < 3; ++k) g.p[k] = vec4(t.p[k], 0.0f);
    g.p[0].w = t.open ? 1.0f : 0.0f;
    int same = 0;
    for (int k = 0; k < 3; ++k) same |= t.same_direction[k] ? 1 << k : 0;
    g.neighbour = glm::ivec4(t.neighbour[0], t.neighbour[1], t.neighbour[2], same);
    data.push_back(g);
  }
  const VkDeviceSize per_light =
      gpu_volume_bytes(tris.size(), context_.limits(), context_.device_name());
  if (data.empty()) data.emplace_back();  // buffers are never empty; counts.x stays 0
  triangles_ =
      gpu::make_device_buffer(context_, data.data(), data.size() * sizeof(GpuVolumeTriangle),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  draw_args_ =
      gpu::Buffer(context_, std::max<size_t>(1, light_count) * sizeof(VkDrawIndirectCommand),
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                      VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                  gpu::MemoryUsage::kDevice);
  using B = gpu::DescriptorBinding;
  const auto ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  extraction_set_layout_ = gpu::DescriptorSetLayout(context_, {B{0, ssbo}, B{1, ssbo}, B{2, ssbo}});
  extraction_layout_ =
      gpu::PipelineLayout(context_, {extraction_set_layout_.handle()}, sizeof(ExtractionPush));
  extraction_pipeline_ = gpu::Pipeline(context_, extraction_layout_.handle(), "silhouettes.comp");
  descriptors_ = std::make_unique<gpu::DescriptorAllocator>(context_);
  gpu::DescriptorWriter w;
  for (size_t i = 0; i < light_count; ++i) {
    outputs_.emplace_back(context_, per_light,
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                          gpu::MemoryUsage::kDevice);
    extraction_sets_.push_back(descriptors_->allocate(extraction_set_layout_));
    w.buffer(extraction_sets_.back(), 0, ssbo, triangles_.handle())
        .buffer(extraction_sets_.back(), 1, ssbo, outputs_.back().handle())
        .buffer(extraction_sets_.back(), 2, ssbo, draw_args_.handle());
  }
  w.commit(context_.device());
  log::debug("shadow volumes on the GPU: {} triangles, {:.1f} MiB of vertices per light",
             tris.size(), static_cast<double>(per_light) / (1 << 20));
}

double StencilShadows::build_on_cpu(const std::vector<Light>& lights, bool back_faces) {
  ILLUM_CHECK(source_ == SilhouetteSource::kCpu, "CPU volumes built for GPU silhouettes");
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<glm::vec4> all, one;
  cpu_ranges_.clear();
  ShadowVolumeStats total;
  for (const Light& l : lights) {
    ShadowVolumeStats st;
    if (lit_in_real_time(l))
      builder_.build(l, back_faces, cap_offset_, &one, &st);
    else
      one.clear();
    cpu_ranges_.emplace_back(static_cast<uint32_t>(all.size()), static_cast<uint32_t>(one.size()));
    all.insert(all.end(), one.begin(), one.end());
    total.caster_triangles += st.caster_triangles;
    total.silhouette_edges += st.silhouette_edges;
    total.volume_triangles += st.volume_triangles;
  }
  if (all.empty()) all.emplace_back(0.0f);
  const VkDeviceSize bytes = all.size() * sizeof(glm::vec4);
  if (!cpu_vertices_ || cpu_vertices_.size() < bytes) {
    context_.wait_idle();
    cpu_vertices_ =
        gpu::Buffer(context_, bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryUsage::kUpload);
  }
  cpu_vertices_.write(all.data(), bytes);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  log::debug("shadow volumes: {} casters, {} silhouette edges, {} triangles, {:.1f} ms",
             total.caster_triangles, total.silhouette_edges, total.volume_triangles, ms);
  return ms;
}

void StencilShadows::record_clear(VkCommandBuffer cmd, size_t light_count) {
  ILLUM_CHECK(source_ == SilhouetteSource::kGpu && light_count == outputs_.size(),
              "GPU silhouettes recorded without their buffers");
  if (light_count == 0) return;
  const std::vector<VkDrawIndirectCommand> empty(light_count, {0, 1, 0, 0});
  vkCmdUpdateBuffer(cmd, draw_args_.handle(), 0, empty.size() * sizeof(VkDrawIndirectCommand),
                    empty.data());
}

void StencilShadows::record_extraction(VkCommandBuffer cmd, const std::vector<Light>& lights,
                                       bool back_faces) {
  ILLUM_CHECK(source_ == SilhouetteSource::kGpu && lights.size() == outputs_.size(),
              "GPU silhouettes recorded without their buffers");
  if (lights.empty()) return;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, extraction_pipeline_.handle());
  const uint32_t triangles = static_cast<uint32_t>(builder_.triangle_count());
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& l = lights[i];
    if (!lit_in_real_time(l) || triangles == 0) continue;
    const int type = l.type == LightType::kPoint ? 0 : l.type == LightType::kSpot ? 1 : 2;
    ExtractionPush push;
    push.position_range = vec4(l.position, l.range);
    push.direction_type = vec4(glm::normalize(l.direction), static_cast<float>(type));
    push.params = vec4(l.cone_half_angle, cap_offset_, back_faces ? 1.0f : 0.0f, 0.0f);
    push.counts = glm::uvec4(triangles, static_cast<uint32_t>(i), 0u, 0u);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, extraction_layout_.handle(), 0, 1,
                            &extraction_sets_[i], 0, nullptr);
    vkCmdPushConstants(cmd, extraction_layout_.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push),
                       &push);
    vkCmdDispatch(cmd, (triangles + kExtractionGroup - 1) / kExtractionGroup, 1, 1);
  }
}

void StencilShadows::record_stencil(VkCommandBuffer cmd, VkDescriptorSet frame_set, size_t light,
                                    StencilDraw what) const {
  const VkPipeline pipeline =
      what == StencilDraw::kRasterized ? count_pipeline_.handle() : stencil_pipeline_.handle();
  const bool gpu = source_ == SilhouetteSource::kGpu;
  if (gpu ? light >= outputs_.size()
          : light >= cpu_ranges_.size() || cpu_ranges_[light].second == 0)
    return;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout_, 0, 1, &frame_set,
                          0, nullptr);
  // Counted against the frame's depth buffer: the volumes are seen from the camera, view 0.
  const PushConstants push{};
  vkCmdPushConstants(cmd, pipeline_layout_, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
  if (what == StencilDraw::kCount) vkCmdSetStencilReference(cmd, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
  const VkDeviceSize offset = 0;
  const VkBuffer vertices = gpu ? outputs_[light].handle() : cpu_vertices_.handle();
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertices, &offset);
  if (gpu) {
    vkCmdDrawIndirect(cmd, draw_args_.handle(), light * sizeof(VkDrawIndirectCommand), 1,
                      sizeof(VkDrawIndirectCommand));
  } else {
    const auto [first, count] = cpu_ranges_[light];
    vkCmdDraw(cmd, count, 1, first, 0);
  }
}

}  // namespace illum::realtime
