// `lpv`: light propagation volumes (docs/realtime-lpv.md). Each frame the reflective shadow
// maps' texels (techniques/rsm.cpp, rsm_views.h) are injected as virtual point lights —
// clamped-cosine lobes in L1 spherical harmonics per colour channel — into the n³ cells of
// each cascade (nested boxes around the camera, lpv_cascades.h), their surfaces into a
// geometry volume of blocking potentials offset by half a cell (shaders/lpv_inject.comp);
// `iterations` propagation steps move the light cell to cell, conserving its flux except where the
// geometry volume blocks it (shaders/lpv_propagate.comp), and every step's light is accumulated;
// the accumulation is resolved into "lpv.accum", which the lighting input of the same name samples
// for the indirect term (shaders/inputs/lpv.glsl).
//
// The working volumes are storage buffers private to the technique (the light ping-pong
// pair, the accumulation, the geometry volume): the injection adds to them with
// compare-and-swap float atomics, and the steps depend on each other inside the one pass,
// with barriers recorded here.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/lpv_cascades.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

constexpr const char* kAccum = "lpv.accum";

// shaders/lpv_common.glsl `LpvParams` (std140).
constexpr int kMaxCascades = 4;
struct LpvUniforms {
  std::array<glm::vec4, kMaxCascades> lo;  // per cascade: xyz its min corner; w its cell size
  glm::ivec4 info;      // x: cells per axis; yzw: the surfel images' width, height, layers
  glm::vec4 far_face;   // x: ΔΩ; y: ∫ω·d dω
  glm::vec4 side_face;  // x: ΔΩ; y: ∫ω·e dω; z: ∫ω·d dω
  glm::ivec4 cascades;  // x: how many; y: mask of those rebuilt; z: mask of those restarting
  glm::vec4 blend;      // x: the weight of a rebuild in the history
};
static_assert(sizeof(LpvUniforms) == 144);

// shaders/inputs/lpv.glsl `LpvInput` (std140).
struct LpvInputUniforms {
  std::array<glm::vec4, kMaxCascades> lo;  // as LpvUniforms::lo; past the last cascade, the last
  glm::vec4 slot;                          // per cascade: its atlas part's z, texture coordinates
  glm::ivec4 info;                         // x: cells per axis; y: cascades
  glm::vec4 params;                        // x: amplification; y: dampening
};
static_assert(sizeof(LpvInputUniforms) == 112);

}  // namespace

LpvFaces lpv_face_integrals(int samples) {
  // Unit cells, the source's centre at the origin, its neighbour along +z: the far face is
  // z = 1.5, |x|, |y| ≤ ½; the side face x = ½, |y| ≤ ½, z ∈ [½, 3⁄2]. Midpoint rule over each
  // square, dω = (distance of the face's plane)/r³ dA.
  LpvFaces f;
  const double h = 1.0 / samples;
  for (int i = 0; i < samples; ++i)
    for (int j = 0; j < samples; ++j) {
      const double u = (i + 0.5) * h - 0.5, v = (j + 0.5) * h - 0.5;
      {
        const double z = 1.5, r = std::sqrt(u * u + v * v + z * z);
        const double dw = z / (r * r * r) * h * h;
        f.far_solid_angle += dw;
        f.far_along += z / r * dw;
      }
      {
        const double x = 0.5, z = v + 1.0, r = std::sqrt(x * x + u * u + z * z);
        const double dw = x / (r * r * r) * h * h;
        f.side_solid_angle += dw;
        f.side_across += x / r * dw;
        f.side_along += z / r * dw;
      }
    }
  return f;
}

namespace {

class Lpv final : public Technique {
 public:
  Lpv(TechniqueContext& ctx, const TechniqueDecl& decl)
      : Technique(ctx, decl), descriptors_(ctx.gpu) {
    using B = gpu::DescriptorBinding;
    constexpr VkDescriptorType kSsbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    constexpr VkDescriptorType kTexture = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    // The injection's set apart: its maps exist only where a source is produced, and every
    // binding of a bound set must hold a descriptor.
    set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, kSsbo}, B{2, kSsbo}, B{3, kSsbo},
                  B{4, kSsbo}, B{9, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
    inject_set_layout_ = gpu::DescriptorSetLayout(
        ctx.gpu, {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, kSsbo}, B{3, kSsbo}, B{5, kTexture},
                  B{6, kTexture}, B{7, kTexture}, B{8, kSsbo}});
    layout_ = gpu::PipelineLayout(ctx.gpu, {set_layout_.handle()}, 0);
    inject_layout_ = gpu::PipelineLayout(ctx.gpu, {inject_set_layout_.handle()}, 0);
    inject_ = gpu::Pipeline(ctx.gpu, inject_layout_.handle(), "lpv_inject.comp");
    propagate_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "lpv_propagate.comp");
    resolve_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "lpv_resolve.comp");
    history_pass_ = gpu::Pipeline(ctx.gpu, layout_.handle(), "lpv_history.comp");
    for (VkDescriptorSet& s : sets_) s = descriptors_.allocate(set_layout_);
    history_set_ = descriptors_.allocate(set_layout_);
    resolve_set_ = descriptors_.allocate(set_layout_);
    inject_set_ = descriptors_.allocate(inject_set_layout_);

    const int grid = param<int>("grid");
    if (grid != 16 && grid != 32 && grid != 64)
      throw Error(fmt::format("-p lpv.grid={}: 16, 32 or 64", grid));
    n_ = static_cast<uint32_t>(grid);
    cascades_ = static_cast<uint32_t>(param<int>("cascades"));
    source_ = param<std::string>("source");
    const VkDeviceSize cells = VkDeviceSize(n_) * n_ * n_ * cascades_;
    const VkDeviceSize corners = VkDeviceSize(n_ + 1) * (n_ + 1) * (n_ + 1) * cascades_;
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    for (gpu::Buffer& b : light_)
      b = gpu::Buffer(ctx.gpu, cells * 12 * sizeof(float), usage, gpu::MemoryUsage::kDevice);
    accumulation_ =
        gpu::Buffer(ctx.gpu, cells * 12 * sizeof(float), usage, gpu::MemoryUsage::kDevice);
    history_ = gpu::Buffer(ctx.gpu, cells * 12 * sizeof(float), usage, gpu::MemoryUsage::kDevice);
    geometry_ = gpu::Buffer(ctx.gpu, corners * 4 * sizeof(float), usage, gpu::MemoryUsage::kDevice);
    uniforms_ = gpu::Buffer(ctx.gpu, sizeof(LpvUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            gpu::MemoryUsage::kUpload);
    input_uniforms_ = gpu::Buffer(ctx.gpu, sizeof(LpvInputUniforms),
                                  VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::kUpload);
    const LpvFaces f = lpv_face_integrals(256);
    u_.far_face = glm::vec4(float(f.far_solid_angle), float(f.far_along), 0.0f, 0.0f);
    u_.side_face =
        glm::vec4(float(f.side_solid_angle), float(f.side_across), float(f.side_along), 0.0f);
    u_.info = glm::ivec4(static_cast<int>(n_), 0, 0, 0);
    u_.cascades = glm::ivec4(static_cast<int>(cascades_), 0, 0, 0);
  }

  void declare(FrameGraph& graph) override {
    // The source is named by the user: the maps must be declared before lpv is (rsm, and
    // shadow methods, declare earlier).
    for (const char* part : {".position", ".normal", ".flux", ".views"})
      if (!graph.has_resource(source_ + part))
        throw Error(fmt::format("-p lpv.source={}: nothing in this frame declares '{}{}'", source_,
                                source_, part));
    ResourceDesc r;
    r.name = kAccum;
    r.width = 4 * n_;  // R, G and B parts side by side, then the DC sum's gradient
    r.height = n_;
    r.depth = n_ * cascades_;  // the cascades one after the other
    r.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    // Read back by tests and shown by -p debug.show=lpv.accum:SLICE.
    r.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    graph.add_resource(r);

    PassDesc p;
    p.name = "lpv";
    p.technique = name();
    // After the reflective shadow maps (same phase, declared later), before every pass that
    // shades.
    p.phase = Phase::kShadows;
    p.accesses = {{kAccum, kStorageWrite, kComputeShader},
                  Access{source_ + ".position", kSampled, kComputeShader}.if_produced(),
                  Access{source_ + ".normal", kSampled, kComputeShader}.if_produced(),
                  Access{source_ + ".flux", kSampled, kComputeShader}.if_produced(),
                  Access{source_ + ".views", kStorageRead, kComputeShader}.if_produced()};
    p.nested_scopes = 2;  // lpv.inject, lpv.propagate
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

  void bind() override {
    gpu::DescriptorWriter w;
    for (int k = 0; k < 2; ++k) {
      // Set k propagates from light_[k] into light_[1 − k].
      w.buffer(sets_[k], 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle())
          .buffer(sets_[k], 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, light_[k].handle())
          .buffer(sets_[k], 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, light_[1 - k].handle())
          .buffer(sets_[k], 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, geometry_.handle())
          .buffer(sets_[k], 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, accumulation_.handle())
          .image(sets_[k], 9, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, ctx_.resources.image(kAccum).view(),
                 VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    }
    // The history pass reads the accumulation (4) into the history (2); the resolve reads the
    // history (4).
    for (const VkDescriptorSet set : {history_set_, resolve_set_})
      w.buffer(set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle())
          .buffer(set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, light_[0].handle())
          .buffer(set, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  set == history_set_ ? history_.handle() : light_[1].handle())
          .buffer(set, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, geometry_.handle())
          .buffer(set, 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  set == history_set_ ? accumulation_.handle() : history_.handle())
          .image(set, 9, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, ctx_.resources.image(kAccum).view(),
                 VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    const std::array<std::string, 4> names = {source_ + ".position", source_ + ".normal",
                                              source_ + ".flux", source_ + ".views"};
    injects_ = std::all_of(names.begin(), names.end(), [&](const std::string& name) {
      return ctx_.graph().reads("lpv", name);
    });
    if (injects_) {
      w.buffer(inject_set_, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle())
          .buffer(inject_set_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, light_[0].handle())
          .buffer(inject_set_, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, geometry_.handle());
      for (uint32_t k = 0; k < 3; ++k)
        w.image(inject_set_, 5 + k, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                ctx_.resources.image(names[k]).view(), ctx_.globals.nearest().handle(),
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      w.buffer(inject_set_, 8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
               ctx_.resources.buffer(names[3]).handle());
      const gpu::ImageDesc& d = ctx_.resources.image(names[0]).desc();
      u_.info = glm::ivec4(static_cast<int>(n_), static_cast<int>(d.width),
                           static_cast<int>(d.height), static_cast<int>(d.layers));
    }
    w.commit(ctx_.gpu.device());
  }

  void update() override {
    const std::vector<LpvCascade> fresh =
        lpv_cascades(ctx_.view().camera.position, static_cast<int>(n_), static_cast<int>(cascades_),
                     param<float>("cell"), ctx_.scene.bounds());
    // Cascade k is rebuilt in the frames f with f ≡ k (mod period), staggered so that one
    // cascade's work falls in a frame; the others keep their light and their box. A rebuild
    // moves the history halfway to the new light, or restarts it where the box moved (its
    // cells hold other places now) or on the first build. Period 1: every cascade, every
    // frame, the history the new light itself.
    const uint32_t period = static_cast<uint32_t>(param<int>("update_period"));
    int rebuilt = 0, restart = 0;
    boxes_.resize(fresh.size());
    built_.resize(fresh.size(), false);
    for (size_t k = 0; k < fresh.size(); ++k) {
      if (built_[k] && period > 1 && frame_ % period != k % period) continue;
      rebuilt |= 1 << k;
      if (!built_[k] || period == 1 || boxes_[k].lo != fresh[k].lo ||
          boxes_[k].cell != fresh[k].cell)
        restart |= 1 << k;
      boxes_[k] = fresh[k];
      built_[k] = true;
    }
    ++frame_;
    const std::vector<LpvCascade>& boxes = boxes_;
    for (size_t k = 0; k < boxes.size(); ++k) u_.lo[k] = vec4(boxes[k].lo, boxes[k].cell);
    u_.cascades = glm::ivec4(static_cast<int>(cascades_), rebuilt, restart, 0);
    u_.blend = vec4(0.5f, 0.0f, 0.0f, 0.0f);
    rebuilt_ = rebuilt;
    uniforms_.write(&u_, sizeof(u_));
    LpvInputUniforms in{};
    for (size_t k = 0; k < in.lo.size(); ++k) {
      const size_t q = std::min(k, boxes.size() - 1);
      in.lo[k] = u_.lo[q];
      in.slot[int(k)] = static_cast<float>(q) / static_cast<float>(cascades_);
    }
    in.info = glm::ivec4(static_cast<int>(n_), static_cast<int>(cascades_), 0, 0);
    in.params = vec4(param<float>("amplification"), param<float>("dampening"), 0.0f, 0.0f);
    input_uniforms_.write(&in, sizeof(in));
  }

  std::vector<LightingContribution> lighting_inputs() const override {
    LightingContribution c;
    c.input = "lpv";
    c.write = [this](gpu::DescriptorWriter& w, VkDescriptorSet set, uint32_t base) {
      w.buffer(set, base, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, input_uniforms_.handle())
          .image(set, base + 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                 ctx_.resources.image(kAccum).view(), ctx_.globals.clamp_linear().handle(),
                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    };
    c.reads = {kAccum};
    return {c};
  }

 private:
  static void barrier(VkCommandBuffer c, VkPipelineStageFlags from, VkAccessFlags from_access,
                      VkPipelineStageFlags to, VkAccessFlags to_access) {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = from_access;
    b.dstAccessMask = to_access;
    vkCmdPipelineBarrier(c, from, to, 0, 1, &b, 0, nullptr, 0, nullptr);
  }

  void record(PassContext& pass) {
    constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
    constexpr VkAccessFlags kShader = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    const VkCommandBuffer c = pass.cmd();
    const uint32_t groups = (n_ + 3) / 4;
    const uint32_t depth_groups = groups * cascades_;  // n is a multiple of 4
    barrier(c, kCompute, kShader, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(c, light_[0].handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(c, geometry_.handle(), 0, VK_WHOLE_SIZE, 0);
    barrier(c, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShader);
    if (injects_) {
      auto scope = pass.scope("lpv.inject");
      vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, inject_layout_.handle(), 0, 1,
                              &inject_set_, 0, nullptr);
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, inject_.handle());
      vkCmdDispatch(c, (uint32_t(u_.info.y) + 7) / 8, (uint32_t(u_.info.z) + 7) / 8,
                    uint32_t(u_.info.w));
    }
    // A rebuilt cascade's accumulation starts as its injected light; the others' stay.
    barrier(c, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kTransfer, VK_ACCESS_TRANSFER_READ_BIT);
    const VkDeviceSize part = light_[0].size() / cascades_;
    std::vector<VkBufferCopy> parts;
    for (uint32_t q = 0; q < cascades_; ++q)
      if (rebuilt_ & (1 << q)) parts.push_back({q * part, q * part, part});
    if (!parts.empty())
      vkCmdCopyBuffer(c, light_[0].handle(), accumulation_.handle(),
                      static_cast<uint32_t>(parts.size()), parts.data());
    barrier(c, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kShader);
    {
      auto scope = pass.scope("lpv.propagate");
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, propagate_.handle());
      const int iterations = param<int>("iterations");
      for (int k = 0; k < iterations; ++k) {
        vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1,
                                &sets_[k % 2], 0, nullptr);
        vkCmdDispatch(c, groups, groups, depth_groups);
        barrier(c, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShader);
      }
    }
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1,
                            &history_set_, 0, nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, history_pass_.handle());
    vkCmdDispatch(c, groups, groups, depth_groups);
    barrier(c, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kShader);
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.handle(), 0, 1,
                            &resolve_set_, 0, nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_.handle());
    vkCmdDispatch(c, groups, groups, depth_groups);
  }

  gpu::DescriptorAllocator descriptors_;
  gpu::DescriptorSetLayout set_layout_, inject_set_layout_;
  gpu::PipelineLayout layout_, inject_layout_;
  VkDescriptorSet inject_set_ = VK_NULL_HANDLE;
  gpu::Pipeline inject_, propagate_, resolve_, history_pass_;
  VkDescriptorSet history_set_ = VK_NULL_HANDLE, resolve_set_ = VK_NULL_HANDLE;
  gpu::Buffer history_;            // per cascade the light the lookup sees (lpv_history.comp)
  std::vector<LpvCascade> boxes_;  // each cascade's box at its last rebuild
  std::vector<bool> built_;
  uint64_t frame_ = 0;
  int rebuilt_ = 0;  // this frame's mask of rebuilt cascades
  std::array<VkDescriptorSet, 2> sets_{};
  std::array<gpu::Buffer, 2> light_;
  gpu::Buffer accumulation_, geometry_, uniforms_, input_uniforms_;
  LpvUniforms u_{};
  uint32_t n_ = 32;
  uint32_t cascades_ = 3;
  std::string source_;
  bool injects_ = false;
};

}  // namespace

TechniqueDecl lpv_technique() {
  TechniqueDecl t;
  t.name = "lpv";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "light propagation volumes (nested cascades around the camera): the reflective shadow "
      "maps injected as SH lobes, propagated cell to cell conserving flux, looked up as the "
      "indirect term";
  t.dependencies = {"rsm"};
  t.params = {
      int_param("grid", 32, 16, 64, "cells along each axis: 16, 32 or 64").structural(),
      int_param("cascades", 3, 1, kMaxCascades,
                "nested volumes around the camera, the cell size doubling from one to the next")
          .structural(),
      float_param("cell", 0.0f, 0.0f, 1e4f,
                  "the finest cascade's cell size (world units), each cascade snapped to its "
                  "own; 0: the coarsest spans the scene's bounds"),
      int_param("iterations", 8, 0, 64, "propagation steps per frame"),
      int_param("update_period", 1, 1, 8,
                "cascade k is rebuilt in frames f with f = k (mod this), the others keep their "
                "light; a rebuild moves the looked-up light halfway"),
      float_param("amplification", 1.0f, 0.0f, 100.0f, "scales the indirect term"),
      float_param("dampening", 1.0f, 0.0f, 4.0f,
                  "scales down light that grows towards the back of a surface (came through "
                  "it): 1 + dampening·(derivative along the normal)/value; 0: off"),
      string_param("source", "rsm",
                   "the maps injected: SOURCE.position, .normal, .flux and .views, laid out "
                   "as the reflective shadow maps' (rsm_views.h)")
          .structural(),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Lpv>(ctx, *find_technique("lpv"));
  };
  return t;
}

}  // namespace illum::realtime
