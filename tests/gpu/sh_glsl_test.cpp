// shaders/sh.glsl against core/sh.h: every function of the include, run on the GPU
// (lavapipe in CI) through shaders/test_sh.comp for random directions, compared with the
// C++ evaluation in double, so the shader constants and formulas cannot drift from the one
// definition. Tolerance: float rounding. Each value is at most 3 roundings of terms ≤ 1.1
// (basis) or a sum of 4 products of terms ≤ 2·0.49 (irradiance over π, coefficients ≤ 1),
// i.e. below 8·2⁻²⁴·1.1 ≈ 5e-7; 1e-6 leaves room for the GPU's fused multiply-adds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "illum/core/sh.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/context.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/pipeline.h"

namespace illum::gpu {
namespace {

TEST(ShGlsl, EveryFunctionMatchesCoreSh) {
  ContextOptions options;
  options.validation = true;
  Context context(options);
  ASSERT_TRUE(context.validation_enabled()) << "VK_LAYER_KHRONOS_validation is required";

  const uint32_t n = 500, stride = 20;
  std::mt19937_64 rng(21);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<glm::dvec3> dirs(n);
  std::vector<float> data(n * stride, 0.0f);
  for (uint32_t i = 0; i < n; ++i) {
    glm::vec3 d = glm::normalize(glm::vec3(float(g(rng)), float(g(rng)), float(g(rng))));
    if (i < 6) {  // the axes too
      d = glm::vec3(0.0f);
      d[i / 2] = i % 2 ? -1.0f : 1.0f;
    }
    dirs[i] = glm::dvec3(d);  // the float direction the GPU gets, exactly
    for (int k = 0; k < 3; ++k) data[i * stride + k] = d[k];
  }
  struct {
    glm::vec4 c[4];
    uint32_t count;
  } push{};
  for (auto& c : push.c) c = glm::vec4(float(u(rng)), float(u(rng)), float(u(rng)), 0.0f);
  push.count = n;

  Buffer buffer =
      make_device_buffer(context, data.data(), data.size() * sizeof(float),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  DescriptorSetLayout set_layout(context, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
  DescriptorAllocator descriptors(context);
  VkDescriptorSet set = descriptors.allocate(set_layout);
  DescriptorWriter()
      .buffer(set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer.handle())
      .commit(context.device());
  PipelineLayout layout(context, {set_layout.handle()}, sizeof(push));
  Pipeline pipeline(context, layout.handle(), "test_sh.comp");
  Buffer readback(context, data.size() * sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                  MemoryUsage::kReadback);
  context.immediate([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 0, 1, &set, 0,
                            nullptr);
    vkCmdPushConstants(cmd, layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (n + 63) / 64, 1, 1);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy copy{0, 0, data.size() * sizeof(float)};
    vkCmdCopyBuffer(cmd, buffer.handle(), readback.handle(), 1, &copy);
  });
  readback.read(data.data(), data.size() * sizeof(float));
  EXPECT_EQ(context.validation_message_count(), 0u) << "validation messages were emitted";

  const double tolerance = 1e-6;
  const std::vector<double> lambda = sh::clamped_cosine_factors(2);
  for (uint32_t i = 0; i < n; ++i) {
    const float* r = &data[i * stride];
    const std::vector<double> y = sh::evaluate(3, dirs[i]);
    for (int k = 0; k < 9; ++k) ASSERT_NEAR(r[4 + k], y[k], tolerance) << "Y" << k << " at " << i;
    for (int k = 0; k < 4; ++k)
      ASSERT_NEAR(r[13 + k], y[k], tolerance) << "L1 " << k << " at " << i;
    for (int ch = 0; ch < 3; ++ch) {
      double e = 0.0;
      for (int k = 0; k < 4; ++k) e += lambda[k == 0 ? 0 : 1] * push.c[k][ch] * y[k];
      ASSERT_NEAR(r[17 + ch], e / std::numbers::pi, tolerance)
          << "E/π channel " << ch << " at " << i;
    }
  }
}

}  // namespace
}  // namespace illum::gpu
