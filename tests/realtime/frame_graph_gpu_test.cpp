// The frame graph's image model on a Vulkan device, with the validation layers watching:
// a mip pyramid built level by level (each level sampled through its own view while the next
// is a storage image; per-level barriers derived by the graph) and a 3-D image written by a
// compute pass and sampled trilinearly. Both run two frames, so the second starts from the
// layouts the first left behind.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/frame_resources.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;
using GpuFrameGraph = test::ValidatedVulkanTest;

uint32_t groups(uint32_t n, uint32_t size) {
  return (n + size - 1) / size;
}

TEST_F(GpuFrameGraph, PyramidLevelsAreMeansOfTheLevelAbove) {
  using namespace gpu;
  Context& ctx = context();
  constexpr uint32_t kSide = 16;
  FrameGraph g;
  ResourceDesc pyramid;
  pyramid.name = "pyramid";
  pyramid.width = pyramid.height = kSide;
  pyramid.format = VK_FORMAT_R32_SFLOAT;
  pyramid.mips = 0;  // the full chain: 5 levels
  pyramid.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  g.add_resource(pyramid);
  const Access write{"pyramid", kStorageWrite, kComputeShader};
  const Access sample{"pyramid", kSampled, kComputeShader};

  DescriptorSetLayout fill_layout(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
  DescriptorSetLayout down_layout(
      ctx, {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
  PipelineLayout fill_pl(ctx, {fill_layout.handle()}, 0), down_pl(ctx, {down_layout.handle()}, 0);
  Pipeline fill(ctx, fill_pl.handle(), "test_pyramid_fill.comp");
  Pipeline down(ctx, down_pl.handle(), "test_pyramid_down.comp");
  Sampler nearest(ctx, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  DescriptorAllocator descriptors(ctx);
  VkDescriptorSet fill_set = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> down_sets;
  uint32_t levels = 0;

  PassDesc fill_pass;
  fill_pass.name = "fill";
  fill_pass.phase = Phase::kScreenSpace;
  fill_pass.accesses = {write.mips(0)};
  fill_pass.record = [&](PassContext& pass) {
    vkCmdBindPipeline(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, fill.handle());
    vkCmdBindDescriptorSets(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, fill_pl.handle(), 0, 1,
                            &fill_set, 0, nullptr);
    vkCmdDispatch(pass.cmd(), groups(kSide, 8), groups(kSide, 8), 1);
  };
  g.add_pass(fill_pass);
  PassDesc down_pass;
  down_pass.name = "downsample";
  down_pass.phase = Phase::kScreenSpace;
  down_pass.accesses = {write.mips(1, kAllSubresources), sample};
  down_pass.record = [&](PassContext& pass) {
    vkCmdBindPipeline(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, down.handle());
    for (uint32_t m = 1; m < levels; ++m) {
      pass.use(sample.mips(m - 1));
      pass.use(write.mips(m));
      vkCmdBindDescriptorSets(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, down_pl.handle(), 0, 1,
                              &down_sets[m - 1], 0, nullptr);
      const uint32_t side = kSide >> m;
      vkCmdDispatch(pass.cmd(), groups(side, 8), groups(side, 8), 1);
    }
  };
  g.add_pass(down_pass);
  g.compile();
  FrameResources resources(ctx);
  resources.realize(g, kSide, kSide);
  GpuImage& image = resources.image("pyramid");
  levels = image.desc().mips;
  ASSERT_EQ(levels, 5u);
  fill_set = descriptors.allocate(fill_layout);
  DescriptorWriter writer;
  writer.image(fill_set, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, image.mip_view(0), VK_NULL_HANDLE,
               VK_IMAGE_LAYOUT_GENERAL);
  for (uint32_t m = 1; m < levels; ++m) {
    down_sets.push_back(descriptors.allocate(down_layout));
    writer
        .image(down_sets.back(), 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
               image.mip_view(m - 1), nearest.handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        .image(down_sets.back(), 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, image.mip_view(m),
               VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
  }
  writer.commit(ctx.device());

  for (uint64_t frame = 0; frame < 2; ++frame) {
    ctx.immediate([&](VkCommandBuffer cmd) { g.execute(cmd, frame, nullptr); });
    // The last level was written, the others sampled: the image's layouts differ by level.
    EXPECT_EQ(image.layout(), VK_IMAGE_LAYOUT_MAX_ENUM);
    const Image top = image.readback(0, 0, 0);
    for (uint32_t m = 1; m < levels; ++m) {
      const Image level = image.readback(0, 0, m);
      const uint32_t side = kSide >> m, block = 1u << m;
      ASSERT_EQ(static_cast<uint32_t>(level.width()), side);
      for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
          double mean = 0.0;
          for (uint32_t j = 0; j < block; ++j)
            for (uint32_t i = 0; i < block; ++i)
              mean +=
                  top.pixel(static_cast<int>(x * block + i), static_cast<int>(y * block + j))[0];
          mean /= block * block;
          // Sums of at most 256 integers below 17, each step ÷4: exact in float.
          ASSERT_EQ(level.pixel(static_cast<int>(x), static_cast<int>(y))[0],
                    static_cast<float>(mean))
              << "level " << m << " texel " << x << ", " << y;
        }
    }
    // Level 0 is the pattern (a frame that skipped the fill would leave zeros).
    EXPECT_EQ(top.pixel(3, 2)[0], static_cast<float>((3 * 7 + 2 * 13) % 17));
  }
}

TEST_F(GpuFrameGraph, VolumeIsSampledTrilinearly) {
  using namespace gpu;
  Context& ctx = context();
  constexpr uint32_t kSide = 8;
  const float c[4] = {0.1f, 0.2f, 0.3f, 0.5f};  // f = 0.1 i + 0.2 j + 0.3 k + 0.5
  FrameGraph g;
  ResourceDesc volume;
  volume.name = "volume";
  volume.width = volume.height = volume.depth = kSide;
  volume.format = VK_FORMAT_R16G16B16A16_SFLOAT;  // linear filtering and storage everywhere
  volume.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  g.add_resource(volume);

  // Points inside the texel centres (0.5/8 .. 7.5/8), where trilinear filtering of a linear
  // function gives the function itself.
  std::vector<float> points;
  std::vector<double> expected;
  for (int n = 0; n < 64; ++n) {
    const float t[3] = {0.5f + 7.0f * ((n * 37) % 64) / 63.0f,
                        0.5f + 7.0f * ((n * 11) % 64) / 63.0f,
                        0.5f + 7.0f * ((n * 23) % 64) / 63.0f};
    points.insert(points.end(), {t[0] / kSide, t[1] / kSide, t[2] / kSide, 0.0f});
    expected.push_back(c[0] * (t[0] - 0.5) + c[1] * (t[1] - 0.5) + c[2] * (t[2] - 0.5) + c[3]);
  }
  const uint32_t count = static_cast<uint32_t>(expected.size());
  Buffer point_buffer = make_device_buffer(ctx, points.data(), points.size() * sizeof(float),
                                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  Buffer values(ctx, count * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryUsage::kReadback);

  DescriptorSetLayout fill_layout(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
  DescriptorSetLayout sample_layout(ctx, {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                          {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                          {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
  PipelineLayout fill_pl(ctx, {fill_layout.handle()}, sizeof(c));
  PipelineLayout sample_pl(ctx, {sample_layout.handle()}, sizeof(count));
  Pipeline fill(ctx, fill_pl.handle(), "test_volume_fill.comp");
  Pipeline sample(ctx, sample_pl.handle(), "test_volume_sample.comp");
  Sampler trilinear(ctx, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  DescriptorAllocator descriptors(ctx);
  VkDescriptorSet fill_set = VK_NULL_HANDLE, sample_set = VK_NULL_HANDLE;

  PassDesc fill_pass;
  fill_pass.name = "fill";
  fill_pass.phase = Phase::kLighting;
  fill_pass.accesses = {{"volume", kStorageWrite, kComputeShader}};
  fill_pass.record = [&](PassContext& pass) {
    vkCmdBindPipeline(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, fill.handle());
    vkCmdBindDescriptorSets(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, fill_pl.handle(), 0, 1,
                            &fill_set, 0, nullptr);
    vkCmdPushConstants(pass.cmd(), fill_pl.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(c), c);
    vkCmdDispatch(pass.cmd(), kSide / 4, kSide / 4, kSide / 4);
  };
  g.add_pass(fill_pass);
  PassDesc sample_pass;
  sample_pass.name = "sample";
  sample_pass.phase = Phase::kPost;
  sample_pass.accesses = {{"volume", kSampled, kComputeShader}};
  sample_pass.record = [&](PassContext& pass) {
    vkCmdBindPipeline(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, sample.handle());
    vkCmdBindDescriptorSets(pass.cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, sample_pl.handle(), 0, 1,
                            &sample_set, 0, nullptr);
    vkCmdPushConstants(pass.cmd(), sample_pl.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(count),
                       &count);
    vkCmdDispatch(pass.cmd(), groups(count, 64), 1, 1);
    memory_barrier(pass.cmd(), VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
  };
  g.add_pass(sample_pass);
  g.compile();
  FrameResources resources(ctx);
  resources.realize(g, 1, 1);
  GpuImage& image = resources.image("volume");
  fill_set = descriptors.allocate(fill_layout);
  sample_set = descriptors.allocate(sample_layout);
  DescriptorWriter()
      .image(fill_set, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, image.view(), VK_NULL_HANDLE,
             VK_IMAGE_LAYOUT_GENERAL)
      .image(sample_set, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, image.view(),
             trilinear.handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
      .buffer(sample_set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, point_buffer.handle())
      .buffer(sample_set, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, values.handle())
      .commit(ctx.device());

  // The bound: each texel is stored in half precision (relative error 2^-11 of at most
  // f_max = 0.6·7 + 0.5), and the filter weights carry subTexelPrecisionBits bits, each
  // axis's weight off by at most 2^-bits times that axis's step between texels.
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(ctx.physical(), &props);
  const double weight_step = std::ldexp(1.0, -static_cast<int>(props.limits.subTexelPrecisionBits));
  const double bound = (0.6 * 7 + 0.5) * std::ldexp(1.0, -11) + (c[0] + c[1] + c[2]) * weight_step;
  for (uint64_t frame = 0; frame < 2; ++frame) {
    ctx.immediate([&](VkCommandBuffer cmd) { g.execute(cmd, frame, nullptr); });
    std::vector<float> got(count);
    values.read(got.data(), count * sizeof(float));
    for (uint32_t i = 0; i < count; ++i)
      ASSERT_NEAR(got[i], expected[i], bound) << "point " << i << " (bound " << bound << ")";
    // A depth slice read back: texel (i, j) of slice k holds f(i, j, k).
    const Image slice = image.readback(5);
    EXPECT_NEAR(slice.pixel(3, 4)[0], c[0] * 3 + c[1] * 4 + c[2] * 5 + c[3], 4.8 * 0x1p-11);
  }
}

}  // namespace
}  // namespace illum::realtime
