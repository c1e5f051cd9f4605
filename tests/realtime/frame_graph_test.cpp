// The frame graph without a GPU: ordering, usage and barrier derivation from declared
// accesses, history copies, schedules (every N with a phase, round-robin, on change) and
// invalidation by what changed. Passes record nothing; execute(VK_NULL_HANDLE, ...) runs
// the schedules and derives the barriers as data.
#include <algorithm>

#include <gtest/gtest.h>

#include "illum/core/error.h"
#include "illum/realtime/frame_graph.h"

namespace illum::realtime {
namespace {

ResourceDesc image(const std::string& name, VkFormat format = VK_FORMAT_R16G16B16A16_SFLOAT) {
  ResourceDesc r;
  r.name = name;
  r.frame_divisor = 1;
  r.format = format;
  return r;
}

ResourceDesc buffer(const std::string& name) {
  ResourceDesc r;
  r.name = name;
  r.kind = ResourceDesc::Kind::kBuffer;
  r.bytes = 64;
  return r;
}

PassDesc pass(const std::string& name, Phase phase, std::vector<Access> accesses,
              Schedule schedule = Schedule::every_frame(), const std::string& technique = "t") {
  PassDesc p;
  p.name = name;
  p.technique = technique;
  p.phase = phase;
  p.accesses = std::move(accesses);
  p.schedule = schedule;
  return p;
}

const Barrier* find_barrier(const std::vector<Barrier>& barriers, const std::string& resource,
                            size_t nth = 0) {
  for (const Barrier& b : barriers)
    if (b.resource == resource && nth-- == 0) return &b;
  return nullptr;
}

size_t count_barriers(const std::vector<Barrier>& barriers, const std::string& resource) {
  size_t n = 0;
  for (const Barrier& b : barriers) n += b.resource == resource;
  return n;
}

TEST(FrameGraph, RunsByPhaseThenDeclarationOrder) {
  FrameGraph g;
  g.add_resource(image("hdr"));
  g.add_resource(image("ldr", VK_FORMAT_R8G8B8A8_UNORM));
  g.add_resource(image("shadow", VK_FORMAT_R32_SFLOAT));
  g.add_pass(pass("tonemap", Phase::kDisplay, {{"hdr", kSampled}, {"ldr", kStorageWrite}}));
  g.add_pass(pass("forward", Phase::kGeometry, {{"shadow", kSampled}, {"hdr", kColorAttachment}}));
  g.add_pass(pass("lighting", Phase::kLighting, {{"hdr", kStorageRead | kStorageWrite}}));
  g.add_pass(pass("shadow", Phase::kShadows, {{"shadow", kColorAttachment}}));
  g.compile();
  EXPECT_EQ(g.order(), (std::vector<std::string>{"shadow", "forward", "lighting", "tonemap"}));
}

TEST(FrameGraph, ReadsNeedAnEarlierWriterAndRequiredOutputsAWriter) {
  {
    FrameGraph g;
    g.add_resource(image("gbuffer"));
    g.add_resource(image("hdr"));
    // The reader's phase comes before the writer's: nothing has written it yet.
    g.add_pass(
        pass("lighting", Phase::kGeometry, {{"gbuffer", kSampled}, {"hdr", kColorAttachment}}));
    g.add_pass(pass("gbuffer", Phase::kLighting, {{"gbuffer", kColorAttachment}}));
    EXPECT_THROW(g.compile(), InternalError);
  }
  {
    FrameGraph g;
    g.add_pass(pass("forward", Phase::kGeometry, {{"undeclared", kColorAttachment}}));
    EXPECT_THROW(g.compile(), InternalError);
  }
  {
    FrameGraph g;
    g.add_resource(image("hdr"));
    g.add_resource(image("ldr", VK_FORMAT_R8G8B8A8_UNORM));
    g.add_pass(pass("forward", Phase::kGeometry, {{"hdr", kColorAttachment}}));
    g.require("ldr", "enable tonemap");
    try {
      g.compile();
      ADD_FAILURE() << "no writer of the required output was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("enable tonemap"), std::string::npos) << e.what();
    }
  }
}

TEST(FrameGraph, UsageIsTheUnionOfTheAccesses) {
  FrameGraph g;
  ResourceDesc hdr = image("hdr");
  hdr.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  g.add_resource(hdr);
  g.add_resource(image("depth", VK_FORMAT_D32_SFLOAT_S8_UINT));
  g.add_resource(buffer("args"));
  g.add_pass(
      pass("gbuffer", Phase::kGeometry,
           {{"hdr", kColorAttachment}, {"depth", kDepthAttachment}, {"args", kTransferDst}}));
  g.add_pass(pass("lighting", Phase::kLighting,
                  {{"depth", kSampled, kComputeShader},
                   {"hdr", kStorageRead | kStorageWrite, kComputeShader},
                   {"args", kIndirectArgs}}));
  g.add_pass(pass("post", Phase::kPost, {{"hdr", kSampled}}));
  g.compile();
  EXPECT_EQ(g.resource("hdr").usage,
            static_cast<uint32_t>(VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                  VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT));
  EXPECT_EQ(g.resource("depth").usage,
            static_cast<uint32_t>(VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                  VK_IMAGE_USAGE_SAMPLED_BIT));
  EXPECT_EQ(g.resource("args").usage, static_cast<uint32_t>(VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                                            VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT));
}

// A deferred frame: every barrier comes from the declared accesses, and only where a hazard
// or a layout change is.
TEST(FrameGraph, BarriersFollowTheDeclaredAccesses) {
  FrameGraph g;
  g.add_resource(image("hdr"));
  g.add_resource(image("depth", VK_FORMAT_D32_SFLOAT_S8_UINT));
  g.add_resource(image("ldr", VK_FORMAT_R8G8B8A8_UNORM));
  g.add_resource(buffer("partials"));
  g.add_pass(
      pass("gbuffer", Phase::kGeometry, {{"hdr", kColorAttachment}, {"depth", kDepthAttachment}}));
  g.add_pass(pass("lighting", Phase::kLighting,
                  {{"depth", kSampled, kComputeShader},
                   {"hdr", kStorageRead | kStorageWrite, kComputeShader}}));
  g.add_pass(
      pass("volumes", Phase::kLighting,
           {{"depth", kDepthReadOnly | kSampled, kFragmentShader}, {"hdr", kColorAttachment}}));
  g.add_pass(
      pass("luminance", Phase::kPost,
           {{"hdr", kSampled, kComputeShader}, {"partials", kStorageWrite, kComputeShader}}));
  g.add_pass(pass("bloom", Phase::kPost, {{"hdr", kSampled, kComputeShader}}));
  g.add_pass(pass("tonemap", Phase::kDisplay,
                  {{"hdr", kSampled, kComputeShader},
                   {"partials", kStorageRead, kComputeShader},
                   {"ldr", kStorageWrite, kComputeShader}}));
  g.compile();
  g.execute(VK_NULL_HANDLE, 0, nullptr);
  const std::vector<Barrier> first = g.barriers();

  // hdr: undefined → colour (gbuffer), → general for the compute read-modify-write (a
  // write after a write), → colour for the volumes, → shader-read for luminance. Bloom
  // reads what luminance's barrier already covered: no barrier; nor for tonemap.
  ASSERT_EQ(count_barriers(first, "hdr"), 4u);
  const Barrier* b = find_barrier(first, "hdr", 0);
  EXPECT_EQ(b->old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(b->new_layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  b = find_barrier(first, "hdr", 1);
  EXPECT_EQ(b->new_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(b->src_stages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
  EXPECT_EQ(b->src_access, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  EXPECT_EQ(b->dst_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(b->dst_access,
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  b = find_barrier(first, "hdr", 3);
  EXPECT_EQ(b->old_layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  EXPECT_EQ(b->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(b->dst_access, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);

  // depth: written, then sampled by compute in the depth read-only layout, then tested and
  // sampled by the fragment stage: same layout, but new stages must see the write.
  ASSERT_EQ(count_barriers(first, "depth"), 3u);
  EXPECT_EQ(find_barrier(first, "depth", 1)->new_layout,
            VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL);
  b = find_barrier(first, "depth", 2);
  EXPECT_EQ(b->old_layout, b->new_layout);
  EXPECT_EQ(b->src_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_NE(b->dst_stages & VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0u);

  // The buffer: its first write needs nothing to wait for; the tonemap read waits for it.
  ASSERT_EQ(count_barriers(first, "partials"), 1u);
  b = find_barrier(first, "partials", 0);
  EXPECT_EQ(b->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  EXPECT_EQ(b->dst_access, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);

  // Next frame: luminance rewrites the buffer tonemap read last frame (write after read: an
  // execution dependency, no memory to make available), and hdr goes from shader-read back
  // to colour.
  g.execute(VK_NULL_HANDLE, 1, nullptr);
  const std::vector<Barrier>& second = g.barriers();
  ASSERT_EQ(count_barriers(second, "partials"), 2u);
  b = find_barrier(second, "partials", 0);
  EXPECT_EQ(b->src_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(b->src_access, VK_ACCESS_2_NONE);
  EXPECT_EQ(b->dst_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  EXPECT_EQ(find_barrier(second, "hdr", 0)->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

// A read by stages the last barrier did not cover gets one (chained from the stages it did
// cover); a read the last barrier covered gets none.
TEST(FrameGraph, ReadsByNewStagesGetABarrier) {
  FrameGraph g;
  g.add_resource(image("shadow", VK_FORMAT_R32_SFLOAT));
  g.add_pass(pass("maps", Phase::kShadows, {{"shadow", kColorAttachment}},
                  Schedule::on_change(kLightsChanged)));
  g.add_pass(pass("forward", Phase::kGeometry, {{"shadow", kSampled, kFragmentShader}}));
  g.add_pass(pass("lighting", Phase::kLighting, {{"shadow", kSampled, kComputeShader}}));
  g.add_pass(pass("again", Phase::kPost, {{"shadow", kSampled, kComputeShader}}));
  g.execute(VK_NULL_HANDLE, 0, nullptr);
  ASSERT_EQ(count_barriers(g.barriers(), "shadow"), 3u);
  const Barrier* b = find_barrier(g.barriers(), "shadow", 2);
  EXPECT_EQ(b->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(b->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(b->src_stages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(b->dst_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  // Next frame nothing rewrites the maps: fragment and compute reads are both covered.
  g.execute(VK_NULL_HANDLE, 1, nullptr);
  EXPECT_EQ(count_barriers(g.barriers(), "shadow"), 0u);
}

TEST(FrameGraph, UseInsideAPassDerivesItsBarrier) {
  FrameGraph g;
  g.add_resource(image("hdr"));
  g.add_resource(image("a"));
  g.add_resource(image("b"));
  g.add_pass(pass("forward", Phase::kGeometry, {{"hdr", kColorAttachment}}));
  PassDesc bloom = pass("bloom", Phase::kPost,
                        {{"hdr", kSampled, kComputeShader},
                         {"a", kStorageWrite, kComputeShader},
                         {"a", kSampled, kComputeShader},
                         {"b", kStorageWrite, kComputeShader}});
  bloom.record = [](PassContext& ctx) {
    ctx.use("a", kSampled, kComputeShader);  // the blur reads what the bright pass wrote
  };
  g.add_pass(bloom);
  g.execute(VK_NULL_HANDLE, 0, nullptr);
  g.compile();
  EXPECT_EQ(g.resource("a").usage,
            static_cast<uint32_t>(VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT));
  ASSERT_EQ(count_barriers(g.barriers(), "a"), 2u);
  const Barrier* b = find_barrier(g.barriers(), "a", 1);
  EXPECT_EQ(b->old_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(b->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(b->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  EXPECT_EQ(count_barriers(g.barriers(), "b"), 1u);  // before the pass: its first access
  // A use the pass did not declare is a wiring bug.
  FrameGraph undeclared;
  undeclared.add_resource(image("a"));
  PassDesc p = pass("p", Phase::kPost, {{"a", kStorageWrite, kComputeShader}});
  p.record = [](PassContext& ctx) { ctx.use("a", kSampled, kComputeShader); };
  undeclared.add_pass(p);
  EXPECT_THROW(undeclared.execute(VK_NULL_HANDLE, 0, nullptr), InternalError);
}

// A temporal resource: "adapt" is what the writer wrote last, "adapt.previous" the one
// before; the copies swap when the writer runs.
TEST(FrameGraph, HistoryResourcesSwapWhenWritten) {
  FrameGraph g;
  ResourceDesc adapt = buffer("adapt");
  adapt.history = true;
  g.add_resource(adapt);
  EXPECT_EQ(g.copies("adapt"), 2);
  std::vector<bool> had_history;
  std::vector<int> written_copy;
  PassDesc p = pass(
      "adaptation", Phase::kPost,
      {{"adapt.previous", kStorageRead, kComputeShader}, {"adapt", kStorageWrite, kComputeShader}});
  p.record = [&](PassContext& ctx) {
    had_history.push_back(ctx.has_history("adapt"));
    written_copy.push_back(ctx.copy("adapt"));
    EXPECT_EQ(ctx.copy("adapt.previous"), 1 - ctx.copy("adapt"));
  };
  g.add_pass(p);
  g.compile();  // reading ".previous" needs no writer this frame
  for (uint64_t f = 0; f < 3; ++f) g.execute(VK_NULL_HANDLE, f, nullptr);
  EXPECT_EQ(had_history, (std::vector<bool>{false, true, true}));
  EXPECT_EQ(written_copy, (std::vector<int>{1, 0, 1}));
  EXPECT_EQ(g.copy_index("adapt"), 1);  // after the frame: the copy written last
  // Frame 2 writes copy 1, which frame 1 read as its previous: write after read.
  const Barrier* b = find_barrier(g.barriers(), "adapt[1]");
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->src_access, VK_ACCESS_2_NONE);
  EXPECT_EQ(b->dst_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  // And reads copy 0, which frame 1 wrote.
  b = find_barrier(g.barriers(), "adapt[0]");
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  FrameGraph bad;
  bad.add_resource(buffer("x"));
  bad.add_pass(pass("p", Phase::kPost, {{"x.previous", kStorageRead}}));
  EXPECT_THROW(bad.compile(), InternalError);  // "x" keeps no history
}

// A writer every third frame and a reader every frame: between writes the reader keeps
// seeing the newest copy (by frame parity it would see the older one every other frame),
// and two writers in one frame swap once.
TEST(FrameGraph, HistoryReadersSeeTheNewestCopyBetweenScheduledWrites) {
  FrameGraph g;
  ResourceDesc trail = buffer("trail");
  trail.history = true;
  g.add_resource(trail);
  std::vector<int> writes;
  PassDesc write =
      pass("write", Phase::kPost, {{"trail", kStorageWrite, kComputeShader}}, Schedule::every_n(3));
  write.record = [&](PassContext& ctx) { writes.push_back(ctx.copy("trail")); };
  g.add_pass(write);
  PassDesc add =
      pass("add", Phase::kPost, {{"trail", kStorageRead | kStorageWrite, kComputeShader}},
           Schedule::every_n(3));
  add.record = [&](PassContext& ctx) { EXPECT_EQ(ctx.copy("trail"), writes.back()); };
  g.add_pass(add);
  std::vector<int> read;
  PassDesc reader = pass("read", Phase::kDisplay, {{"trail", kStorageRead, kComputeShader}});
  reader.record = [&](PassContext& ctx) { read.push_back(ctx.copy("trail")); };
  g.add_pass(reader);
  g.compile();
  for (uint64_t f = 0; f < 7; ++f) g.execute(VK_NULL_HANDLE, f, nullptr);
  EXPECT_EQ(writes, (std::vector<int>{1, 0, 1}));  // frames 0, 3, 6
  EXPECT_EQ(read, (std::vector<int>{1, 1, 1, 0, 0, 0, 1}));
}

// A pyramid built level by level: each level is written as a storage image while the level
// above is sampled. Every level keeps its own state: each step puts a barrier on the levels
// it touches only, and a later whole-image read needs one for the last level alone.
TEST(FrameGraph, MipLevelsKeepTheirOwnStateInAPyramid) {
  FrameGraph g;
  ResourceDesc pyramid = image("pyramid", VK_FORMAT_R32_SFLOAT);
  pyramid.frame_divisor = 0;
  pyramid.width = pyramid.height = 16;
  pyramid.mips = 5;
  g.add_resource(pyramid);
  g.add_resource(image("out"));
  const Access write{"pyramid", kStorageWrite, kComputeShader};
  const Access sample{"pyramid", kSampled, kComputeShader};
  g.add_pass(pass("fill", Phase::kScreenSpace, {write.mips(0)}));
  PassDesc down = pass("downsample", Phase::kScreenSpace, {write.mips(1, 4), sample.mips(0, 4)});
  down.record = [&](PassContext& ctx) {
    for (uint32_t m = 1; m < 5; ++m) {
      ctx.use(sample.mips(m - 1));
      ctx.use(write.mips(m));
    }
  };
  g.add_pass(down);
  g.add_pass(pass("use", Phase::kPost, {sample, {"out", kStorageWrite, kComputeShader}}));
  g.compile();
  g.execute(VK_NULL_HANDLE, 0, nullptr);
  std::vector<const Barrier*> b;
  for (const Barrier& x : g.barriers())
    if (x.resource == "pyramid") b.push_back(&x);
  // fill: level 0 to GENERAL; the downsample's first access: levels 1–4 to GENERAL in one
  // barrier.
  ASSERT_GE(b.size(), 3u);
  EXPECT_EQ(b[0]->base_mip, 0u);
  EXPECT_EQ(b[0]->mip_count, 1u);
  EXPECT_EQ(b[0]->new_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(b[1]->base_mip, 1u);
  EXPECT_EQ(b[1]->mip_count, 4u);
  EXPECT_EQ(b[1]->new_layout, VK_IMAGE_LAYOUT_GENERAL);
  // Every level m − 1 is made readable once, just before level m is written.
  for (uint32_t m = 1; m < 5; ++m) {
    auto it = std::find_if(b.begin(), b.end(), [&](const Barrier* x) {
      return x->base_mip == m - 1 && x->mip_count == 1 &&
             x->new_layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    });
    ASSERT_NE(it, b.end()) << "level " << m - 1;
    EXPECT_EQ((*it)->old_layout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ((*it)->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  }
  // The whole-image read at the end: only level 4 is still GENERAL, one barrier for it;
  // levels 0–3 are already readable.
  const Barrier* last = b.back();
  EXPECT_EQ(last->base_mip, 4u);
  EXPECT_EQ(last->mip_count, 1u);
  EXPECT_EQ(last->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  // Frame 1: levels 0–3 go from SHADER_READ back to GENERAL for writing, level 4 too; the
  // downsample's first access covers levels 1–4 in one barrier (same old state).
  g.execute(VK_NULL_HANDLE, 1, nullptr);
  const Barrier* again = find_barrier(g.barriers(), "pyramid", 1);
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(again->base_mip, 1u);
  EXPECT_EQ(again->mip_count, 4u);
  EXPECT_EQ(again->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  // Ranges outside the image are wiring bugs.
  FrameGraph bad;
  bad.add_resource(pyramid);
  bad.add_pass(pass("p", Phase::kPost, {write.mips(5)}));
  EXPECT_THROW(bad.execute(VK_NULL_HANDLE, 0, nullptr), InternalError);
}

// Layers of a cube map rendered one face at a time then sampled whole: per-face barriers
// while rendering, then one barrier over the six faces that share their state.
TEST(FrameGraph, LayersRenderedOneAtATimeAreReadInOneBarrier) {
  FrameGraph g;
  ResourceDesc cube = image("cube", VK_FORMAT_R16G16B16A16_SFLOAT);
  cube.frame_divisor = 0;
  cube.width = cube.height = 8;
  cube.layers = 6;
  cube.cube = true;
  g.add_resource(cube);
  g.add_resource(image("out"));
  const Access face{"cube", kColorAttachment};
  PassDesc capture = pass("capture", Phase::kGeometry, {face});
  capture.record = [&](PassContext& ctx) {
    for (uint32_t f = 1; f < 6; ++f) ctx.use(face.layers(f));
  };
  g.add_pass(capture);
  g.add_pass(pass("read", Phase::kPost, {{"cube", kSampled}, {"out", kColorAttachment}}));
  g.compile();
  // Each frame: the first access takes all six faces in one barrier; each later face finds
  // its layer written by that access's scope and gets a write-after-write barrier of its
  // own layer only; the read covers the six faces, which share their state, in one.
  for (uint64_t frame = 0; frame < 2; ++frame) {
    g.execute(VK_NULL_HANDLE, frame, nullptr);
    ASSERT_EQ(count_barriers(g.barriers(), "cube"), 7u);
    const Barrier* first = find_barrier(g.barriers(), "cube", 0);
    EXPECT_EQ(first->base_layer, 0u);
    EXPECT_EQ(first->layer_count, 6u);
    for (uint32_t f = 1; f < 6; ++f) {
      const Barrier* b = find_barrier(g.barriers(), "cube", f);
      EXPECT_EQ(b->base_layer, f);
      EXPECT_EQ(b->layer_count, 1u);
    }
  }
  const Barrier* read = find_barrier(g.barriers(), "cube", 6);
  EXPECT_EQ(read->base_layer, 0u);
  EXPECT_EQ(read->layer_count, 6u);
  EXPECT_EQ(read->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

std::vector<std::string> run(FrameGraph& g, uint64_t frame) {
  return g.execute(VK_NULL_HANDLE, frame, nullptr);
}

TEST(FrameGraph, SchedulesEveryFrameEveryNWithPhaseAndOnChange) {
  FrameGraph g;
  for (const char* r : {"x", "y", "z", "w"}) g.add_resource(buffer(r));
  g.add_pass(pass("a", Phase::kGeometry, {{"x", kStorageWrite}}));
  g.add_pass(pass("b", Phase::kGeometry, {{"y", kStorageWrite}}, Schedule::every_n(3)));
  g.add_pass(pass("c", Phase::kGeometry, {{"z", kStorageWrite}}, Schedule::every_n(3, 1)));
  g.add_pass(pass("d", Phase::kGeometry, {{"w", kStorageWrite}},
                  Schedule::on_change(kLightsChanged | kParametersChanged), "shadows"));
  using V = std::vector<std::string>;
  EXPECT_EQ(run(g, 0), (V{"a", "b", "c", "d"}));  // everything runs on the first frame
  EXPECT_EQ(run(g, 1), (V{"a"}));
  EXPECT_EQ(run(g, 2), (V{"a", "c"}));  // (2 + 1) % 3 == 0
  EXPECT_EQ(run(g, 3), (V{"a", "b"}));
  g.notify(kCameraChanged);  // not what d depends on
  EXPECT_EQ(run(g, 4), (V{"a"}));
  g.notify(kLightsChanged);
  EXPECT_EQ(run(g, 5), (V{"a", "c", "d"}));
  g.notify(kParametersChanged, "tonemap");  // another technique's parameter
  EXPECT_EQ(run(g, 6), (V{"a", "b"}));
  g.notify(kParametersChanged, "shadows");
  EXPECT_EQ(run(g, 7), (V{"a", "d"}));
  g.invalidate_writers("w");
  EXPECT_EQ(run(g, 8), (V{"a", "c", "d"}));
}

// k of n items a frame in turn (cube faces), all of them after a change they depend on.
TEST(FrameGraph, RoundRobinUpdatesKOfNItemsAFrame) {
  FrameGraph g;
  g.add_resource(buffer("faces"));
  std::vector<std::vector<int>> seen;
  PassDesc p = pass("cube", Phase::kShadows, {{"faces", kStorageWrite}},
                    Schedule::round_robin(6, 2, kLightsChanged));
  p.record = [&](PassContext& ctx) { seen.push_back(ctx.items()); };
  g.add_pass(p);
  for (uint64_t f = 0; f < 5; ++f) run(g, f);
  g.notify(kLightsChanged);
  run(g, 5);
  run(g, 6);
  using V = std::vector<std::vector<int>>;
  EXPECT_EQ(seen,
            (V{{0, 1, 2, 3, 4, 5}, {0, 1}, {2, 3}, {4, 5}, {0, 1}, {0, 1, 2, 3, 4, 5}, {2, 3}}));
}

TEST(FrameGraph, InheritKeepsTheScheduleOfKeptTechniques) {
  auto build = [](FrameGraph& g) {
    g.add_resource(buffer("maps"));
    g.add_resource(buffer("bloom"));
    g.add_pass(pass("shadow_maps", Phase::kShadows, {{"maps", kStorageWrite}},
                    Schedule::on_change(kLightsChanged), "map"));
    g.add_pass(pass("bloom", Phase::kPost, {{"bloom", kStorageWrite}},
                    Schedule::on_change(kParametersChanged), "bloom"));
  };
  FrameGraph old;
  build(old);
  run(old, 0);
  FrameGraph next;
  build(next);
  // Bloom was rebuilt: it runs again; the shadow maps were kept and stay cached.
  next.inherit(old, [](const std::string& technique) { return technique != "bloom"; });
  EXPECT_EQ(run(next, 1), (std::vector<std::string>{"bloom"}));
}

TEST(FrameGraph, TimerScopesCountPassesAndTheirNestedScopes) {
  FrameGraph g;
  g.add_resource(buffer("x"));
  PassDesc lights = pass("volumes", Phase::kLighting, {{"x", kStorageWrite}});
  lights.nested_scopes = 8;  // two per light, four lights
  g.add_pass(lights);
  PassDesc cpu = pass("cpu_build", Phase::kShadows, {});
  cpu.cpu = true;
  g.add_pass(cpu);
  g.add_pass(pass("post", Phase::kPost, {{"x", kStorageRead}}));
  EXPECT_EQ(g.timer_scopes(), 1u + 8u + 1u);
  run(g, 0);
  ASSERT_EQ(g.cpu_times().size(), 1u);
  EXPECT_EQ(g.cpu_times()[0].name, "cpu:cpu_build");
}

}  // namespace
}  // namespace illum::realtime
