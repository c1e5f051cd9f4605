// The camera block (FrameGlobals::add_views, common.glsl `views`): a technique draws the scene
// with a frame pipeline's variant from a view of its own. The forward variant drawn from an
// added view (another frame's camera) into a target of the technique's is, bit for bit, the
// frame the renderer draws with that camera as its main view; the depth-only variant drawn
// from view k is the shadow-style draw (shadow_depth.vert: the view's transform pushed with
// the model); the block hands out and takes back its views.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

#include "illum/gpu/gpu_image.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/renderer.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/techniques/frame_targets.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

using test::context;

class Views : public test::ValidatedVulkanTest {};

constexpr uint32_t kWidth = 96, kHeight = 80;

// The Cornell box with a glossy tall block: the specular highlight moves with the camera the
// fragment stage takes its view direction from, not only with the vertex transform.
Scene glossy_cornell() {
  Scene s = test::cornell_point_light();
  Material glossy = s.materials[0];
  glossy.type = MaterialType::kPhong;
  glossy.specular = Color(0.4f);
  glossy.exponent = 40.0f;
  s.materials.push_back(glossy);
  s.meshes[5].material = 3;  // the tall block's mesh (after the five walls)
  return s;
}

// The main camera (view 0) and a second one, looking at the box from the side.
Camera main_camera(const Scene& s) {
  return *s.camera;
}
Camera side_camera() {
  Camera c;
  c.position = vec3(1.6f, 0.8f, 1.9f);
  c.look_at = vec3(0.45f, 0.35f, 0.4f);
  c.fov_y = radians(45.0f);
  return c;
}

RenderSettings forward_settings() {
  RenderSettings o;
  o.width = static_cast<int>(kWidth);
  o.height = static_cast<int>(kHeight);
  o.pipeline = "forward";
  o.shadows = "none";
  return o;
}

gpu::GpuImage target(VkFormat format) {
  gpu::ImageDesc d;
  d.width = kWidth;
  d.height = kHeight;
  d.format = format;
  d.usage = (gpu::is_depth_format(format) ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                                          : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT) |
            VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  return gpu::GpuImage(context(), d);
}

// What a technique holds to draw the scene itself: the uploaded scene, the frame globals with
// view 0 the main camera and one added view, the scene draw service.
struct TechniqueLike {
  const Scene& scene;
  RenderSettings settings = forward_settings();
  GpuScene gpu_scene;
  FrameGlobals globals;
  SceneDrawer drawer;
  ViewSlots slots;

  explicit TechniqueLike(const Scene& s)
      : scene(s),
        gpu_scene(context(), s),
        globals(context(), gpu_scene, realtime_lights(s).size()),
        drawer(gpu_scene, globals) {
    const std::vector<Light> lights = realtime_lights(s);
    globals.upload_lights(lights);
    globals.update(camera_view(main_camera(s), gpu_scene.bounds(), kWidth, kHeight), settings,
                   lights.size(), kWidth, kHeight);
    slots = globals.add_views(1);
  }
  // Puts `camera` in the added view; returns that view.
  FrameView set_added(const Camera& camera) {
    const FrameView v = camera_view(camera, gpu_scene.bounds(), kWidth, kHeight);
    globals.set_view(slots[0], v, {kWidth, kHeight});
    return v;
  }
  std::array<VkDescriptorSet, 3> neutral_sets() const {
    return {globals.neutral_set(kPipelineSet), globals.neutral_set(kShadowSet),
            globals.neutral_set(kShadowSet + 1)};
  }
};

// The forward pipeline's variants as forward.cpp builds them: the depth pre-pass, then the
// shading with depth EQUAL.
struct ForwardVariants {
  gpu::Pipeline prepass, shade;
  ForwardVariants(VkPipelineLayout layout, VkFormat depth) {
    gpu::GraphicsPipelineDesc fwd;
    fwd.vertex_shader = "forward.vert";
    fwd.fragment_shader = "forward.frag";
    fwd.vertex_input = mesh_vertex_input(false);
    fwd.cull = VK_CULL_MODE_NONE;
    fwd.color_formats = {kHdrFormat};
    fwd.depth_format = depth;
    fwd.stencil_format = depth;
    gpu::GraphicsPipelineDesc pre = fwd;
    pre.vertex_shader = "depth_only.vert";
    pre.vertex_input = mesh_vertex_input(true);
    pre.fragment_shader = "depth_only.frag";
    pre.color_formats = {};
    pre.color_write = false;
    prepass = gpu::Pipeline(context(), layout, pre);
    fwd.depth_write = false;
    fwd.depth_compare = VK_COMPARE_OP_EQUAL;
    shade = gpu::Pipeline(context(), layout, fwd);
  }
};

void to_attachment(VkCommandBuffer c, gpu::GpuImage& image) {
  if (gpu::is_depth_format(image.desc().format))
    image.transition(
        c, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  else
    image.transition(c, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

// The forward variants drawn from view `view` of `t`'s block into a fresh HDR target.
Image forward_from(TechniqueLike& t, int view, const mat4& view_proj) {
  const VkFormat depth_format = gpu::pick_depth_stencil_format(context());
  const ForwardVariants variants(t.globals.default_layout(), depth_format);
  gpu::GpuImage hdr = target(kHdrFormat), depth = target(depth_format);
  context().immediate([&](VkCommandBuffer c) {
    to_attachment(c, hdr);
    to_attachment(c, depth);
    DrawTargets pre;
    pre.depth = depth.view();
    pre.stencil = true;
    pre.extent = {kWidth, kHeight};
    t.drawer.render(c, pre, {&variants.prepass}, t.globals.default_layout(), t.neutral_sets(),
                    SceneView::from(view, view_proj, true));
    depth.transition(
        c, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
    DrawTargets shade;
    shade.colors = {{hdr.view(), true, {}}};
    shade.depth = depth.view();
    shade.clear_depth = false;
    shade.stencil = true;
    shade.extent = {kWidth, kHeight};
    t.drawer.render(c, shade, {&variants.shade}, t.globals.default_layout(), t.neutral_sets(),
                    SceneView::from(view, view_proj, false));
  });
  return hdr.readback();
}

size_t differing_pixels(const Image& a, const Image& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.data().size(); i += 4)
    n += std::memcmp(&a.data()[i], &b.data()[i], 4 * sizeof(float)) != 0;
  return n;
}

// Covered pixels (alpha 1: forward.frag writes it, the clear leaves 0).
size_t covered(const Image& a) {
  size_t n = 0;
  for (size_t i = 3; i < a.data().size(); i += 4) n += a.data()[i] == 1.0f;
  return n;
}

TEST_F(Views, ForwardFromAnAddedViewIsTheFrameWithThatCameraAsTheMainView) {
  const Scene scene = glossy_cornell();
  Renderer renderer(context(), scene, forward_settings());
  renderer.render(side_camera());
  const Image frame = renderer.hdr();
  renderer.render(main_camera(scene));
  const Image main_frame = renderer.hdr();

  TechniqueLike t(scene);
  const FrameView side = t.set_added(side_camera());
  const Image drawn = forward_from(t, static_cast<int>(t.slots[0]), side.view_proj);
  ASSERT_EQ(drawn.width(), frame.width());
  EXPECT_GT(covered(drawn), kWidth * kHeight / 2);
  // The two cameras see different frames, so equality says which camera each stage took.
  EXPECT_GT(differing_pixels(frame, main_frame), kWidth * kHeight / 2);
  EXPECT_EQ(differing_pixels(drawn, frame), 0u) << "of " << kWidth * kHeight << " pixels";
  EXPECT_TRUE(test::identical(drawn, frame));
  // View 0 of the same block is the main camera's frame.
  const FrameView main = camera_view(main_camera(scene), t.gpu_scene.bounds(), kWidth, kHeight);
  EXPECT_TRUE(test::identical(forward_from(t, 0, main.view_proj), main_frame));
}

// Depth of `view` into a fresh D32 target, by `variant`; `clip_from_world` set: the
// shadow-style draw (the view's transform pushed with the model, shadow_depth.vert).
Image depth_from(TechniqueLike& t, const gpu::Pipeline& variant, int view, const mat4& view_proj,
                 bool pushed_transform) {
  gpu::GpuImage depth = target(VK_FORMAT_D32_SFLOAT);
  context().immediate([&](VkCommandBuffer c) {
    to_attachment(c, depth);
    DrawTargets d;
    d.depth = depth.view();
    d.extent = {kWidth, kHeight};
    SceneView v = SceneView::from(view, view_proj, true);
    v.per_draw = false;
    if (pushed_transform) v.clip_from_world = view_proj;
    t.drawer.render(c, d, {&variant}, t.globals.default_layout(), t.neutral_sets(), v);
  });
  return depth.readback(0, VK_IMAGE_ASPECT_DEPTH_BIT);
}

TEST_F(Views, DepthVariantFromViewKIsTheShadowStyleDraw) {
  const Scene scene = glossy_cornell();
  TechniqueLike t(scene);
  const FrameView side = t.set_added(side_camera());
  gpu::GraphicsPipelineDesc d;
  d.vertex_shader = "depth_only.vert";
  d.fragment_shader = "depth_only.frag";
  d.vertex_input = mesh_vertex_input(true);
  d.cull = VK_CULL_MODE_NONE;
  d.depth_format = VK_FORMAT_D32_SFLOAT;
  const gpu::Pipeline by_view(context(), t.globals.default_layout(), d);
  d.vertex_shader = "shadow_depth.vert";
  const gpu::Pipeline by_push(context(), t.globals.default_layout(), d);

  const int k = static_cast<int>(t.slots[0]);
  const Image a = depth_from(t, by_view, k, side.view_proj, false);
  const Image b = depth_from(t, by_push, 0, side.view_proj, true);
  const FrameView main = camera_view(main_camera(scene), t.gpu_scene.bounds(), kWidth, kHeight);
  const Image from_main = depth_from(t, by_view, 0, main.view_proj, false);
  size_t written = 0, differ_from_main = 0;
  for (size_t i = 0; i < a.data().size(); ++i) {
    written += a.data()[i] < 1.0f;
    differ_from_main += a.data()[i] != from_main.data()[i];
  }
  EXPECT_GT(written, kWidth * kHeight / 2);
  EXPECT_GT(differ_from_main, kWidth * kHeight / 2);
  // The scene's instances have identity transforms, so view × (model × p) and
  // (view × model) × p round alike: the depths are equal bit for bit.
  EXPECT_TRUE(test::identical(a, b));
}

TEST_F(Views, TheBlockHandsOutContiguousViewsAndTakesThemBack) {
  const Scene scene = glossy_cornell();
  GpuScene gpu_scene(context(), scene);
  FrameGlobals globals(context(), gpu_scene, 1);
  {
    ViewSlots a = globals.add_views(3);
    ViewSlots b = globals.add_views(2);
    EXPECT_EQ(a[0], 1u);  // view 0 is the frame's camera
    EXPECT_EQ(a[2], 3u);
    EXPECT_EQ(b[0], 4u);
    EXPECT_THROW(globals.add_views(kMaxViews - 5), Error);
    ViewSlots c = globals.add_views(kMaxViews - 6);
    EXPECT_EQ(c[0], 6u);
    ViewSlots moved = std::move(a);
    EXPECT_EQ(a.size(), 0u);
    EXPECT_EQ(moved[1], 2u);
  }
  // All given back when the holders went.
  EXPECT_EQ(globals.add_views(kMaxViews - 1)[0], 1u);
  EXPECT_THROW(globals.set_view(0, FrameView{}, {1, 1}), InternalError);
}

}  // namespace
}  // namespace illum::realtime
