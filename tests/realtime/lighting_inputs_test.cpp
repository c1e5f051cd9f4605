// The lighting-inputs set (set 4, realtime/lighting_inputs.h) on lavapipe under the validation
// layer:
// * its layout is the union of the registered inputs' ranges, and the shaders' set-4
//   bindings (read from the embedded SPIR-V of the gathering shaders) are exactly those, with
//   the same descriptor types: C++ and GLSL share one bindings header and cannot drift;
// * with no contributing technique the ambient term is the neutral default, albedo ·
//   ambient, in every frame pipeline (and a technique switched on without data leaves the
//   frame's bytes alone);
// * a screen-space input (SSAO) switched on and off on a running renderer gives a fresh
//   renderer's frames in every pipeline (the deferred G-buffer takes up and drops its
//   indirect target);
// * two occlusion contributions combine by minimum on the GPU, through the input modules'
//   own code (shaders/test_inputs_occlusion.comp), and an inactive input leaves the term open.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"
#include "illum/gpu/shader_library.h"
#include "illum/realtime/gpu_types.h"
#include "illum/realtime/lighting_inputs.h"
#include "illum/realtime/renderer.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

class LightingInputsTest : public test::ValidatedVulkanTest {};

// The set-4 bindings a SPIR-V module declares, with their descriptor types.
std::map<uint32_t, VkDescriptorType> set4_bindings(std::span<const uint32_t> words) {
  constexpr uint32_t kOpTypeSampledImage = 27, kOpTypeImage = 25, kOpTypePointer = 32,
                     kOpVariable = 59, kOpDecorate = 71, kDecorationBinding = 33,
                     kDecorationSet = 34;
  constexpr uint32_t kUniformConstant = 0, kUniform = 2, kStorageBuffer = 12;
  std::map<uint32_t, uint32_t> set, binding, pointer_class, pointer_type, variable_type;
  std::set<uint32_t> sampled_images, images;
  for (size_t i = 5; i < words.size();) {
    const uint32_t op = words[i] & 0xffffu, count = words[i] >> 16;
    const uint32_t* w = &words[i];
    if (op == kOpDecorate && w[2] == kDecorationSet) set[w[1]] = w[3];
    if (op == kOpDecorate && w[2] == kDecorationBinding) binding[w[1]] = w[3];
    if (op == kOpTypeSampledImage) sampled_images.insert(w[1]);
    if (op == kOpTypeImage) images.insert(w[1]);
    if (op == kOpTypePointer) {
      pointer_class[w[1]] = w[2];
      pointer_type[w[1]] = w[3];
    }
    if (op == kOpVariable) variable_type[w[2]] = w[1];
    i += std::max(count, 1u);
  }
  std::map<uint32_t, VkDescriptorType> out;
  for (const auto& [id, s] : set) {
    if (s != static_cast<uint32_t>(kInputsSet)) continue;
    const uint32_t ptr = variable_type.at(id);
    const uint32_t storage = pointer_class.at(ptr), pointee = pointer_type.at(ptr);
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
    if (storage == kUniform) type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    if (storage == kStorageBuffer) type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    if (storage == kUniformConstant && sampled_images.count(pointee))
      type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    if (storage == kUniformConstant && images.count(pointee))
      type = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    out[binding.at(id)] = type;
  }
  return out;
}

TEST(LightingInputsLayout, IsTheUnionOfTheRegisteredInputsAndTheShadersAgree) {
  // The layout: the state block, then each input's range, without overlaps or gaps.
  std::map<uint32_t, VkDescriptorType> layout;
  for (const gpu::DescriptorBinding& b : lighting_inputs_layout()) {
    EXPECT_TRUE(layout.emplace(b.binding, b.type).second) << "binding " << b.binding << " twice";
  }
  size_t expected = 1;
  std::set<int> indices;
  for (const LightingInputDecl& d : lighting_input_registry()) {
    EXPECT_TRUE(indices.insert(d.index).second) << d.name;
    EXPECT_LT(d.index, kMaxLightingInputs) << d.name;
    EXPECT_EQ(find_lighting_input(d.name), &d);
    expected += d.bindings.size();
    for (size_t k = 0; k < d.bindings.size(); ++k) {
      const auto it = layout.find(static_cast<uint32_t>(d.base) + static_cast<uint32_t>(k));
      ASSERT_NE(it, layout.end()) << d.name << " binding " << k;
      EXPECT_EQ(it->second, d.bindings[k].type) << d.name << " binding " << k;
    }
  }
  EXPECT_EQ(layout.size(), expected);
  EXPECT_EQ(layout.rbegin()->first + 1, static_cast<uint32_t>(kInputBindings));
  EXPECT_EQ(layout.at(kInputsStateBinding), VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
  // The shaders that gather every input declare exactly these bindings and types.
  for (const char* shader : {"forward.frag", "visibility_resolve.comp"}) {
    const std::map<uint32_t, VkDescriptorType> declared = set4_bindings(gpu::shader_spirv(shader));
    EXPECT_EQ(declared, layout) << shader;
  }
  // The deferred G-buffer pass reads the surface inputs only, its late pass the screen-space
  // ones: together, the set.
  std::map<uint32_t, VkDescriptorType> deferred = set4_bindings(gpu::shader_spirv("gbuffer.frag"));
  for (const auto& [b, t] : set4_bindings(gpu::shader_spirv("deferred_inputs.comp")))
    deferred[b] = t;
  // But `vpl`'s: a screen-space indirect term, which the late pass does not take (it applies
  // occlusion only, and the vpl add-on refuses the deferred pipeline).
  std::map<uint32_t, VkDescriptorType> deferred_layout = layout;
  deferred_layout.erase(static_cast<uint32_t>(kVplInputBase));
  EXPECT_EQ(deferred, deferred_layout);
}

// A box without lights or emission: the frame is the ambient term alone.
Scene unlit_box() {
  Scene s = test::cornell_point_light();
  s.lights.clear();
  return s;
}

Image frame(const Scene& scene, const std::string& pipeline, Color ambient, bool baked_on) {
  RenderSettings o;
  o.width = o.height = 48;
  o.pipeline = pipeline;
  o.shadows = "none";
  o.set("lighting.ambient", ambient);
  if (baked_on) o.enable("baked");  // on, but no data: it contributes no input
  Renderer r(context(), scene, o);
  r.render(*scene.camera);
  return r.hdr();
}

TEST_F(LightingInputsTest, WithoutContributionsTheAmbientIsAlbedoTimesTheConstant) {
  const Scene scene = unlit_box();
  const Color ambient(0.4f, 0.8f, 1.6f);
  for (const std::string pipeline : {"forward", "deferred", "visibility"}) {
    const Image lit = frame(scene, pipeline, ambient, false);
    const Image dark = frame(scene, pipeline, Color(0.0f), false);
    EXPECT_TRUE(test::identical(lit, frame(scene, pipeline, ambient, true)))
        << pipeline << ": a technique without data changed the frame";
    int white = 0, covered = 0;
    for (int y = 0; y < lit.height(); ++y)
      for (int x = 0; x < lit.width(); ++x) {
        const float* p = lit.pixel(x, y);
        const float* q = dark.pixel(x, y);
        if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) continue;  // background
        ++covered;
        // One of the box's materials × the constant, to the fp16 target's rounding.
        bool matched = false;
        for (const Material& m : scene.materials) {
          bool all = true;
          for (int c = 0; c < 3; ++c) {
            const double expected = m.albedo[c] * ambient[c];
            all = all && std::abs(p[c] - q[c] - expected) <= 2e-3 * expected + 1e-6;
          }
          matched = matched || all;
          if (all && &m == &scene.materials[0]) ++white;
        }
        EXPECT_TRUE(matched) << pipeline << " " << x << "," << y << ": " << p[0] << " " << p[1]
                             << " " << p[2];
      }
    EXPECT_GT(covered, lit.width() * lit.height() / 2) << pipeline;
    EXPECT_GT(white, covered / 3) << pipeline;
  }
}

// A screen-space input switched on and off on a running renderer (the viewer's toggle): the
// pipeline is kept, so the deferred G-buffer pass must take up and drop its indirect target
// when the frame is re-assembled. Each frame equals a fresh renderer's, and SSAO darkens.
TEST_F(LightingInputsTest, ScreenSpaceInputSwitchedOnARunningRendererMatchesAFreshOne) {
  const Scene scene = test::cornell_point_light();
  for (const std::string pipeline : {"deferred", "forward", "visibility"}) {
    RenderSettings off;
    off.width = off.height = 48;
    off.pipeline = pipeline;
    off.shadows = "none";
    off.set("lighting.ambient", Color(0.5f));
    RenderSettings on = off;
    on.enable("ssao");
    on.set("ssao.radius", 0.2f);
    auto fresh = [&](const RenderSettings& o) {
      Renderer r(context(), scene, o);
      r.render(*scene.camera);
      return r.hdr();
    };
    const Image fresh_off = fresh(off), fresh_on = fresh(on);
    Renderer r(context(), scene, off);
    r.render(*scene.camera);
    r.configure(on);
    r.render(*scene.camera);
    const Image toggled_on = r.hdr();
    r.configure(off);
    r.render(*scene.camera);
    EXPECT_TRUE(test::identical(toggled_on, fresh_on)) << pipeline << ": switched on";
    EXPECT_TRUE(test::identical(r.hdr(), fresh_off)) << pipeline << ": switched off";
    int darker = 0;
    for (int y = 0; y < fresh_on.height(); ++y)
      for (int x = 0; x < fresh_on.width(); ++x)
        darker += fresh_on.pixel(x, y)[1] < fresh_off.pixel(x, y)[1] - 1e-3f;
    EXPECT_GT(darker, 20) << pipeline << ": SSAO darkened nothing";
  }
}

TEST_F(LightingInputsTest, TwoOcclusionContributionsCombineByMinimum) {
  using namespace gpu;
  Context& ctx = context();
  // The occlusion image: one value per pixel of a 5×1 image.
  const std::vector<float> ao = {1.0f, 0.75f, 0.5f, 0.2f, 0.0f};
  Image values(static_cast<int>(ao.size()), 1, 2, 0.0f);
  for (size_t i = 0; i < ao.size(); ++i) values.pixel(static_cast<int>(i), 0)[0] = ao[i];
  ImageDesc d;
  d.width = static_cast<uint32_t>(ao.size());
  d.format = VK_FORMAT_R32G32_SFLOAT;
  d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  GpuImage image(ctx, d);
  image.upload(values);
  std::vector<glm::ivec4> cases;
  for (int a = 0; a < static_cast<int>(ao.size()); ++a)
    for (int b = 0; b < static_cast<int>(ao.size()); ++b) cases.push_back({a, 0, b, 0});
  const uint32_t n = static_cast<uint32_t>(cases.size());
  Buffer in = make_device_buffer(ctx, cases.data(), n * sizeof(glm::ivec4),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  Buffer out(ctx, n * sizeof(glm::vec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
             MemoryUsage::kReadback);
  Buffer state(ctx, 2 * sizeof(glm::ivec4), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
               MemoryUsage::kUpload);
  Sampler nearest(ctx, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  // The kernel's bindings: set 2 its cases and results, set 4 the state block and the
  // `ssao` input's image at their registered bindings.
  const auto ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  const LightingInputDecl* ssao = find_lighting_input("ssao");
  ASSERT_NE(ssao, nullptr);
  const uint32_t image_binding = static_cast<uint32_t>(ssao->base);
  DescriptorSetLayout empty(ctx, {}), io(ctx, {{0, ssbo}, {1, ssbo}});
  DescriptorSetLayout inputs(
      ctx, {{static_cast<uint32_t>(kInputsStateBinding), VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
            {image_binding, ssao->bindings[0].type}});
  DescriptorAllocator descriptors(ctx);
  const VkDescriptorSet io_set = descriptors.allocate(io);
  const VkDescriptorSet inputs_set = descriptors.allocate(inputs);
  DescriptorWriter()
      .buffer(io_set, 0, ssbo, in.handle())
      .buffer(io_set, 1, ssbo, out.handle())
      .buffer(inputs_set, static_cast<uint32_t>(kInputsStateBinding),
              VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, state.handle())
      .image(inputs_set, image_binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, image.view(),
             nearest.handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
      .commit(ctx.device());
  PipelineLayout layout(
      ctx, {empty.handle(), empty.handle(), io.handle(), empty.handle(), inputs.handle()},
      sizeof(PushConstants));
  Pipeline pipeline(ctx, layout.handle(), "test_inputs_occlusion.comp");
  auto run = [&](bool active) {
    glm::ivec4 flags[2] = {};
    flags[ssao->index / 4][ssao->index % 4] = active ? 1 : 0;
    state.write(flags, sizeof(flags));
    ctx.immediate([&](VkCommandBuffer cmd) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
      const VkDescriptorSet sets[] = {io_set, inputs_set};
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 2, 1, &sets[0],
                              0, nullptr);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(),
                              static_cast<uint32_t>(kInputsSet), 1, &sets[1], 0, nullptr);
      PushConstants push{};
      push.material = static_cast<int32_t>(n);
      vkCmdPushConstants(cmd, layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
      vkCmdDispatch(cmd, (n + 63) / 64, 1, 1);
    });
    std::vector<glm::vec2> got(n);
    out.read(got.data(), n * sizeof(glm::vec2));
    return got;
  };
  const std::vector<glm::vec2> on = run(true);
  for (uint32_t i = 0; i < n; ++i) {
    const float expected =
        std::min(ao[static_cast<size_t>(cases[i].x)], ao[static_cast<size_t>(cases[i].z)]);
    EXPECT_EQ(on[i].x, expected) << ao[static_cast<size_t>(cases[i].x)] << ", "
                                 << ao[static_cast<size_t>(cases[i].z)];
    EXPECT_EQ(on[i].y, expected) << "no indirect term holds visibility here";
  }
  for (const glm::vec2& r : run(false)) EXPECT_EQ(r.x, 1.0f) << "an inactive input occluded";
}

}  // namespace
}  // namespace illum::realtime
