// The whole light-map pipeline against the oracle: the built-in Cornell box's atlas is
// built, a plain light-map holding all light is path-traced into it, written and read back
// as a folder, and shown by the real-time renderer (emission + albedo × E/π, no real-time
// lights). Every surface of the box is Lambertian, so that frame estimates the same
// radiance as a path-traced image of the same camera: they must agree up to noise and the
// light-map's texel resolution.
#include <algorithm>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "illum/atlas/atlas.h"
#include "illum/atlas/lightmap_file.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/realtime/baked_lightmap.h"
#include "illum/realtime/renderer.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "test_scene.h"

namespace illum::realtime {
namespace {

namespace fs = std::filesystem;
using test::context;

constexpr int kSize = 96;  // frame side
constexpr int kBlock = 8;  // comparison block side (pixels)

struct BlockStats {
  double within_fraction = 0.0;  // blocks whose mean luminance agrees within the tolerance
  double mean_ratio = 0.0;       // Σ frame luminance / Σ reference luminance
};

// Pixels within 3 pixels of an emitter in either image. The emitter is 50 times brighter
// than any lit wall, and the path tracer filters its edges over neighbouring pixels while
// the rasterizer takes one sample per pixel: measured on this scene, the emitter's border
// alone moved the image sums by 6% while the rest agreed within 0.4%. Emission is not what
// a light-map holds, so those pixels are left out.
std::vector<uint8_t> near_emitters(const Image& frame, const Image& reference) {
  float brightest = 0.0f;
  for (int y = 0; y < reference.height(); ++y)
    for (int x = 0; x < reference.width(); ++x)
      brightest = std::max(brightest, luminance(reference.rgb(x, y)));
  const float threshold = 0.05f * brightest;
  const int w = frame.width(), h = frame.height(), r = 3;
  std::vector<uint8_t> mask(size_t(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (luminance(frame.rgb(x, y)) <= threshold && luminance(reference.rgb(x, y)) <= threshold)
        continue;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u >= 0 && v >= 0 && u < w && v < h) mask[size_t(v) * w + u] = 1;
        }
    }
  return mask;
}

// Compares 8×8-pixel block means of luminance over the pixels not masked: averaging over a
// block takes the per-pixel noise of both estimates down by about 8 and compares shading at
// the scale of a light-map texel rather than the texel grid's bilinear steps.
BlockStats compare_blocks(const Image& frame, const Image& reference,
                          const std::vector<uint8_t>& masked, double tolerance) {
  BlockStats s;
  int blocks = 0, within = 0;
  double sum_f = 0.0, sum_r = 0.0;
  for (int by = 0; by + kBlock <= frame.height(); by += kBlock)
    for (int bx = 0; bx + kBlock <= frame.width(); bx += kBlock) {
      double f = 0.0, r = 0.0;
      int n = 0;
      for (int y = by; y < by + kBlock; ++y)
        for (int x = bx; x < bx + kBlock; ++x) {
          if (masked[size_t(y) * frame.width() + x]) continue;
          f += luminance(frame.rgb(x, y));
          r += luminance(reference.rgb(x, y));
          ++n;
        }
      if (n < kBlock * kBlock / 2) continue;  // mostly emitter
      sum_f += f;
      sum_r += r;
      ++blocks;
      within += std::abs(f - r) <= tolerance * std::max(r, 1e-3 * n) ? 1 : 0;
    }
  s.within_fraction = double(within) / blocks;
  s.mean_ratio = sum_f / sum_r;
  return s;
}

class TempFolder {
 public:
  TempFolder() {
    std::random_device random;
    path_ = fs::temp_directory_path() / ("illum-lightmap-test-" + std::to_string(random()));
    fs::create_directories(path_);
  }
  ~TempFolder() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

TEST(LightmapDisplay, CornellLightmapFrameMatchesPathTracer) {
  ASSERT_TRUE(context().validation_enabled()) << "VK_LAYER_KHRONOS_validation is required";
  const size_t messages_before = context().validation_message_count();

  // Bake: atlas, raster, 128 spp per texel of all light.
  Scene baked_scene = load_scene(ILLUM_DATA_DIR "/scenes/cornell/cornell.illum.json");
  atlas::make_meshes_unique(baked_scene);
  atlas::AtlasOptions atlas_options;
  atlas_options.resolution = 128;
  atlas::LightmapSet set;
  set.atlas = atlas::build_atlas(baked_scene, atlas_options);
  atlas::apply_atlas(baked_scene, set.atlas);
  const RayTracer bake_tracer(baked_scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(baked_scene, 128, 128);
  bake::LightmapBakeOptions bake_options;
  bake_options.spp = 128;
  bake_options.seed = 7;
  bake_options.progress = false;
  bake::LightmapBake baked = bake::bake_lightmap(baked_scene, bake_tracer, raster, bake_options);
  set.basis = "plain";
  set.content = "all";
  set.layers = std::move(baked.layers);
  set.scene = baked_scene.name;
  set.scene_triangles = baked_scene.triangle_count();

  // Through the folder format, as `illum bake` and `illum frame --lightmap` do.
  TempFolder folder;
  save_lightmap_set(folder.path() / "cornell", set);
  const atlas::LightmapSet loaded = atlas::load_lightmap_set(folder.path() / "cornell");

  const Scene original = load_scene(ILLUM_DATA_DIR "/scenes/cornell/cornell.illum.json");
  Scene shown = original;
  const Lightmap lightmap = prepare_lightmap_display(shown, loaded);
  EXPECT_TRUE(shown.lights.empty()) << "content 'all' leaves no real-time light";
  const Camera camera = *original.camera;

  RendererOptions options;
  options.width = options.height = kSize;
  options.shadows = ShadowMode::kNone;
  Renderer renderer(context(), shown, options);
  renderer.set_lightmap(lightmap);
  renderer.render(camera);
  const Image frame = renderer.hdr();

  // The oracle: the path tracer, all light, same camera.
  Params path_params(nlohmann::json::object(), "test");
  auto path = Integrator::create("path", path_params);
  RenderOptions render_options;
  render_options.width = render_options.height = kSize;
  render_options.spp = 256;
  render_options.seed = 3;
  render_options.progress = false;
  const RayTracer tracer(original);
  const Image reference = path->render(tracer, camera, render_options);

  // Tolerance: a block mean of the 256-spp reference has a relative standard error of a
  // few per cent on the box's walls, the light-map's own noise is smaller (128 spp per
  // texel, several texels per block), and single-sample rasterization of geometry edges
  // (the path tracer antialiases them) plus bilinear texel steps along shadow and contact
  // edges shift some block means by more. 15% per block on 85% of the blocks, and 3% on the
  // whole image's sum, leave room for those and still fail a light-map that is wrong by a
  // constant 10% (checked below).
  const std::vector<uint8_t> masked = near_emitters(frame, reference);
  const BlockStats s = compare_blocks(frame, reference, masked, 0.15);
  EXPECT_GE(s.within_fraction, 0.85);
  EXPECT_NEAR(s.mean_ratio, 1.0, 0.03);

  // The comparison is able to fail: the same frame with 10% too much light does.
  Image brighter = frame;
  for (float& v : brighter.data()) v *= 1.1f;
  EXPECT_GT(std::abs(compare_blocks(brighter, reference, masked, 0.15).mean_ratio - 1.0), 0.03);

  EXPECT_EQ(context().validation_message_count(), messages_before);
  std::printf("blocks within 15%%: %.1f%%, mean ratio %.4f\n", 100.0 * s.within_fraction,
              s.mean_ratio);
}

}  // namespace
}  // namespace illum::realtime
