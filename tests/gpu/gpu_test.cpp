// gpu/ layer: device creation, sub-allocator, buffers, images, compute, timers, all under the
// validation layer (any validation message fails the test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "illum/core/error.h"
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

// Render targets and textures go to DEVICE_LOCAL memory or nowhere: on a
// device with host memory only for the image the choice throws naming the image and the
// device; a software device accepts host memory explicitly; DEVICE_LOCAL wins whenever the
// image may use it, whatever the type order.
TEST(ImageMemory, DeviceLocalOrAClearErrorUnlessSoftware) {
  VkPhysicalDeviceMemoryProperties p{};
  p.memoryTypeCount = 3;
  p.memoryTypes[0].propertyFlags =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  p.memoryTypes[1].propertyFlags = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
  p.memoryTypes[2].propertyFlags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  EXPECT_EQ(image_memory_type(p, 0b111, false, "image 8x8 rgba8", "gpu"), 2u);
  EXPECT_EQ(image_memory_type(p, 0b111, true, "image 8x8 rgba8", "cpu"), 2u);
  try {
    image_memory_type(p, 0b011, false, "image 1920x1080 rgba16f", "Some GPU");
    ADD_FAILURE() << "host memory accepted for a render target";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("image 1920x1080 rgba16f"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'Some GPU'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("DEVICE_LOCAL"), std::string::npos) << e.what();
  }
  EXPECT_EQ(image_memory_type(p, 0b010, true, "image 8x8 rgba8", "llvmpipe"), 1u);
}

// On this device a render target lands in DEVICE_LOCAL memory (lavapipe flags its one
// memory type so), or the device is a software one.
TEST_F(GpuTest, RenderTargetIsInDeviceLocalMemory) {
  ImageDesc d;
  d.width = 16;
  d.height = 8;
  d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
  d.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  GpuImage image(*context_, d);
  const VkMemoryPropertyFlags flags =
      context_->allocator().properties().memoryTypes[image.memory_type()].propertyFlags;
  EXPECT_TRUE((flags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) || context_->is_software());
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

// Upload builds the mip chain by 2:1 linear blits, each level from the one above. A 2:1
// linear blit samples the source exactly at the shared corner of each 2×2 block (weights
// 1/2, exact on any sub-texel grid), so every texel of level m must be the mean of its 2×2
// block in level m − 1, as read back (the level actually used, so one rounding does not
// count twice). The result is then stored in the format: float32 within a few ulp of a
// value ≤ 1 (1e-6), fp16 within one fp16 ulp (2⁻¹⁰ relative, either rounding direction),
// 8-bit UNORM within one code: lavapipe filters 8-bit texels in 8-bit fixed point, two
// lerps each rounded half up (≤ ½ code each), so a level can sit a full code above the
// exact mean (measured: texels 235, 48, 67, 170, mean 130, stored 131). Every level
// down to 1×1 and every channel is compared; the source is random so that a filter other
// than the box (nearest texel, a wider tent, a level built from the wrong one) shows.
TEST_F(GpuTest, ImageUploadWithMipsAndReadback) {
  constexpr uint32_t kWidth = 16, kHeight = 8, kMips = 5;  // 16×8 … 1×1
  Image src(kWidth, kHeight, 4);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (float& v : src.data()) v = unit(rng);
  for (VkFormat f :
       {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM}) {
    ImageDesc desc;
    desc.width = kWidth;
    desc.height = kHeight;
    desc.mips = kMips;
    desc.format = f;
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    GpuImage image(*context_, desc);
    image.upload(src);
    auto tolerance = [f](float v) {
      if (f == VK_FORMAT_R8G8B8A8_UNORM) return 1.0f / 255.0f + 1e-6f;
      if (f == VK_FORMAT_R16G16B16A16_SFLOAT) return std::ldexp(std::max(std::abs(v), 1.0f), -10);
      return 1e-6f;
    };
    const char* name = f == VK_FORMAT_R32G32B32A32_SFLOAT   ? "rgba32f"
                       : f == VK_FORMAT_R16G16B16A16_SFLOAT ? "rgba16f"
                                                            : "rgba8";
    // Level 0 is the upload itself, rounded once to the format (half a step).
    Image above = image.readback(0, 0, 0);
    ASSERT_EQ(above.width(), static_cast<int>(kWidth));
    const float upload_tol = f == VK_FORMAT_R8G8B8A8_UNORM        ? 0.5f / 255.0f + 1e-6f
                             : f == VK_FORMAT_R16G16B16A16_SFLOAT ? std::ldexp(1.0f, -11)
                                                                  : 0.0f;
    for (size_t i = 0; i < src.data().size(); ++i)
      ASSERT_NEAR(above.data()[i], src.data()[i], upload_tol) << name << " level 0, value " << i;
    double worst = 0.0;  // of |error| / tolerance over the levels below 0
    for (uint32_t m = 1; m < kMips; ++m) {
      const Image level = image.readback(0, 0, m);
      ASSERT_EQ(level.width(), std::max(1, above.width() / 2)) << name << " level " << m;
      ASSERT_EQ(level.height(), std::max(1, above.height() / 2)) << name << " level " << m;
      for (int y = 0; y < level.height(); ++y)
        for (int x = 0; x < level.width(); ++x)
          for (int k = 0; k < 4; ++k) {
            // A side already at 1 texel is not halved: both "rows" are the same one.
            const int x0 = std::min(2 * x, above.width() - 1),
                      x1 = std::min(2 * x + 1, above.width() - 1);
            const int y0 = std::min(2 * y, above.height() - 1),
                      y1 = std::min(2 * y + 1, above.height() - 1);
            const float expected = 0.25f * (above.pixel(x0, y0)[k] + above.pixel(x1, y0)[k] +
                                            above.pixel(x0, y1)[k] + above.pixel(x1, y1)[k]);
            const float got = level.pixel(x, y)[k];
            worst = std::max(worst, double(std::abs(got - expected)) / tolerance(expected));
            ASSERT_NEAR(got, expected, tolerance(expected))
                << name << " level " << m << " texel (" << x << ", " << y << ") channel " << k;
          }
      above = level;
    }
    std::printf("%s: mips 1..%u within %.3f of their tolerance\n", name, kMips - 1, worst);
  }
}

}  // namespace
}  // namespace illum::gpu
