// gpu/ layer: device creation, sub-allocator, buffers, images, compute, timers, all under the
// validation layer (any validation message fails the test).
#include <gtest/gtest.h>

#include <random>

#include "illum/gpu/buffer.h"
#include "illum/gpu/context.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/gpu_timer.h"
#include "illum/gpu/pipeline.h"
#include "illum/gpu/shader_library.h"

namespace illum::gpu {
namespace {

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ContextOptions options;
    options.validation = true;
    context_ = new Context(options);
  }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(context_->validation_enabled()) << "VK_LAYER_KHRONOS_validation is required";
    before_ = context_->validation_message_count();
  }
  void TearDown() override {
    EXPECT_EQ(context_->validation_message_count(), before_) << "validation messages were emitted";
  }
  static Context* context_;
  size_t before_ = 0;
};
Context* GpuTest::context_ = nullptr;

TEST_F(GpuTest, DeviceHasRequiredFeatures) {
  EXPECT_FALSE(context_->device_name().empty());
  // lavapipe 22.3 has no descriptor indexing; the renderer must not depend on it.
  RecordProperty("descriptor_indexing", context_->descriptor_indexing() ? 1 : 0);
  EXPECT_FALSE(shader_spirv("test_scale.comp").empty());
  EXPECT_TRUE(shader_spirv("no_such.comp").empty());
}

TEST_F(GpuTest, BadDeviceFilterThrowsNamingTheFilter) {
  ContextOptions options;
  options.validation = false;
  options.device_filter = "no-such-gpu-xyz";
  try {
    Context c(options);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-gpu-xyz"), std::string::npos);
  }
}

TEST_F(GpuTest, AllocatorReusesAndMergesFreedRanges) {
  Allocator& a = context_->allocator();
  const AllocatorStats start = a.stats();
  std::mt19937 rng(7);
  std::vector<Buffer> buffers;
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < 40; ++i) {
      const VkDeviceSize size = 256 + rng() % (256 << 10);
      buffers.emplace_back(*context_, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                           MemoryUsage::kDevice);
    }
    std::shuffle(buffers.begin(), buffers.end(), rng);
    buffers.resize(buffers.size() / 2);
  }
  EXPECT_GT(a.stats().used_bytes, start.used_bytes);
  buffers.clear();
  const AllocatorStats end = a.stats();
  // Everything freed merges back into whole blocks, which are released.
  EXPECT_EQ(end.used_bytes, start.used_bytes);
  EXPECT_EQ(end.blocks, start.blocks);
  // A dedicated allocation for a large request.
  Buffer big(*context_, Allocator::kBlockSize / 2, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
             MemoryUsage::kDevice);
  EXPECT_EQ(a.stats().dedicated, start.dedicated + 1);
}

TEST_F(GpuTest, ComputeRoundTripThroughStagingBuffers) {
  const uint32_t n = 1000;
  std::vector<float> values(n);
  for (uint32_t i = 0; i < n; ++i) values[i] = static_cast<float>(i) * 0.5f;
  Buffer data =
      make_device_buffer(*context_, values.data(), n * sizeof(float),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  DescriptorSetLayout set_layout(*context_, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
  DescriptorAllocator descriptors(*context_);
  VkDescriptorSet set = descriptors.allocate(set_layout);
  DescriptorWriter()
      .buffer(set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, data.handle())
      .commit(context_->device());
  PipelineLayout layout(*context_, {set_layout.handle()}, 12);
  Pipeline pipeline(*context_, layout.handle(), "test_scale.comp");
  Buffer readback(*context_, n * sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                  MemoryUsage::kReadback);
  GpuTimer timer(*context_);
  context_->immediate([&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    const uint32_t scope = timer.begin(cmd, "scale");
    struct {
      float scale, offset;
      uint32_t count;
    } push{2.0f, 1.0f, n};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 0, 1, &set, 0,
                            nullptr);
    vkCmdPushConstants(cmd, layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (n + 63) / 64, 1, 1);
    timer.end(cmd, scope);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy copy{0, 0, n * sizeof(float)};
    vkCmdCopyBuffer(cmd, data.handle(), readback.handle(), 1, &copy);
  });
  std::vector<float> out(n);
  readback.read(out.data(), n * sizeof(float));
  for (uint32_t i = 0; i < n; ++i) ASSERT_FLOAT_EQ(out[i], values[i] * 2.0f + 1.0f) << i;
  if (timer.supported()) {
    const auto times = timer.resolve();
    ASSERT_EQ(times.size(), 1u);
    EXPECT_GE(times[0].ms, 0.0);
  }
}

TEST_F(GpuTest, ImageUploadWithMipsAndReadback) {
  Image src(16, 8, 4);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) {
      float* p = src.pixel(x, y);
      p[0] = x / 15.0f;
      p[1] = y / 7.0f;
      p[2] = 0.25f;
      p[3] = 1.0f;
    }
  for (VkFormat f :
       {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM}) {
    ImageDesc desc;
    desc.width = 16;
    desc.height = 8;
    desc.mips = 4;
    desc.format = f;
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    GpuImage image(*context_, desc);
    image.upload(src);
    const Image back = image.readback();
    const float tol = f == VK_FORMAT_R8G8B8A8_UNORM ? 0.5f / 255.0f + 1e-6f : 1e-3f;
    for (size_t i = 0; i < src.data().size(); ++i)
      ASSERT_NEAR(back.data()[i], src.data()[i], tol) << i;
  }
}

}  // namespace
}  // namespace illum::gpu
