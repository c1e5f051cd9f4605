// The whole light-map pipeline against the oracle: the built-in Cornell box's atlas is
// built, a plain light-map holding all light is path-traced into it, written and read back
// as a folder, and shown by the real-time renderer (emission + albedo × E/π, no real-time
// lights). Every surface of the box is Lambertian, so that frame estimates the same
// radiance as a path-traced image of the same camera: they must agree up to noise and the
// light-map's texel resolution.
#include <algorithm>
#include <filesystem>
#include <random>

#include <glm/gtc/packing.hpp>

#include <gtest/gtest.h>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/baked/lightmap_file.h"
#include "illum/realtime/baked_lightmap.h"
#include "illum/realtime/renderer.h"
#include "illum/render/integrator.h"
#include "illum/scene/geometry_hash.h"
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
  baked::LightmapSet set;
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
  set.scene_hash = geometry_hash_hex(baked_scene);

  // Through the folder format, as `illum bake` and `illum frame --baked` do.
  TempFolder folder;
  save_lightmap_set(folder.path() / "cornell", set);
  const baked::LightmapSet loaded = baked::load_lightmap_set(folder.path() / "cornell");

  const Scene original = load_scene(ILLUM_DATA_DIR "/scenes/cornell/cornell.illum.json");
  Scene shown = original;
  const Lightmap lightmap = prepare_lightmap_display(shown, loaded);
  EXPECT_TRUE(shown.lights.empty()) << "content 'all' leaves no real-time light";
  const Camera camera = *original.camera;

  RenderSettings options;
  options.width = options.height = kSize;
  options.shadows = "none";
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

// Light-map display per pixel, with maps that change from texel to texel (random, on a
// 16×8 atlas) on a quad whose uv1 covers a sub-rectangle of the atlas turned by 90° against
// its uv0 and its position: a flipped, swapped or offset uv1, or a layer read from the wrong
// slice, moves every pixel by about the texel-to-texel change (tens of per cent), while a
// correct display agrees with the CPU reference within the bilinear filter's sub-texel
// precision. Plain, RNM and SH-L1 maps; the quad carries a constant tilted normal map so
// RNM's and SH-L1's directional terms weigh the layers unequally.
namespace uv1 {

constexpr int kFrame = 32, kMapW = 16, kMapH = 8;

// Random layer values in [lo, hi], rounded to fp16 as the upload (R16G16B16A16_SFLOAT)
// stores them, so the reference reads what the GPU reads.
Image random_layer(float lo, float hi, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(lo, hi);
  Image im(kMapW, kMapH, 3);
  for (float& v : im.data()) v = glm::unpackHalf1x16(glm::packHalf1x16(value(rng)));
  return im;
}

// Clamp-to-edge bilinear lookup (the light-map sampler), texel centres at (i + 0.5)/size.
Color bilinear_clamped(const Image& im, vec2 uv) {
  const float x = uv.x * im.width() - 0.5f, y = uv.y * im.height() - 0.5f;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float tx = x - x0, ty = y - y0;
  auto at = [&](int i, int j) {
    return im.rgb(std::clamp(i, 0, im.width() - 1), std::clamp(j, 0, im.height() - 1));
  };
  return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
         ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
}

// 2^-bits × (largest neighbour step along x plus along y) of one layer: the most the GPU's
// quantized filter weights can move a lookup.
float filter_error(const Image& im) {
  const int bits = static_cast<int>(context().limits().subTexelPrecisionBits);
  float sx = 0.0f, sy = 0.0f;
  for (int y = 0; y < im.height(); ++y)
    for (int x = 0; x < im.width(); ++x)
      for (int k = 0; k < 3; ++k) {
        if (x + 1 < im.width())
          sx = std::max(sx, std::abs(im.pixel(x, y)[k] - im.pixel(x + 1, y)[k]));
        if (y + 1 < im.height())
          sy = std::max(sy, std::abs(im.pixel(x, y)[k] - im.pixel(x, y + 1)[k]));
      }
  return std::ldexp(sx + sy, -bits);
}

// uv1 at a point (x, y) of the quad z = 0, |x|, |y| ≤ 1: u1 follows y, v1 follows −x, inside
// [0.2, 0.8] × [0.25, 0.75] of the atlas.
vec2 uv1_at(float x, float y) {
  return {0.5f + 0.3f * y, 0.5f - 0.25f * x};
}

Scene quad(const vec3& n_ts) {
  Scene s;
  Material m;
  m.albedo = Color(0.5f, 0.6f, 0.7f);
  Texture t;
  t.srgb = false;
  t.image = Image(4, 4, 4, 1.0f);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int k = 0; k < 3; ++k) t.image.pixel(x, y)[k] = n_ts[k] * 0.5f + 0.5f;
  s.textures.push_back(t);
  m.normal_texture = 0;
  s.materials.push_back(m);
  Mesh q;
  q.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  q.normals.assign(4, vec3(0, 0, 1));
  q.tangents.assign(4, vec4(1, 0, 0, 1));
  q.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  for (const vec3& p : q.positions) q.uv1.push_back(uv1_at(p.x, p.y));
  q.indices = {0, 1, 2, 0, 2, 3};
  s.meshes.push_back(q);
  s.instances.push_back({"", 0, mat4(1.0f)});
  Camera c;
  c.position = vec3(0, 0, 2);
  c.look_at = vec3(0, 0, 0);
  c.fov_y = radians(30.0f);  // the quad fills the frame: no edges to exclude
  s.camera = c;
  return s;
}

}  // namespace uv1

TEST(LightmapDisplay, NonConstantMapsFollowUv1PerPixel) {
  using namespace uv1;
  ASSERT_TRUE(context().validation_enabled()) << "VK_LAYER_KHRONOS_validation is required";
  const size_t messages_before = context().validation_message_count();
  // The normal map stores 8-bit codes of n; the reference uses the normal decoded from them.
  const vec3 wanted = glm::normalize(vec3(0.5f, -0.3f, 0.8f));
  vec3 n;
  for (int k = 0; k < 3; ++k)
    n[k] = std::round((wanted[k] * 0.5f + 0.5f) * 255.0f) / 255.0f * 2.0f - 1.0f;
  n = glm::normalize(n);
  const Scene scene = quad(wanted);
  const Color albedo = scene.materials[0].albedo;
  RenderSettings options;
  options.width = options.height = kFrame;
  options.shadows = "none";
  Renderer renderer(context(), scene, options);

  // Per kind: the layers and each layer's weight in the displayed value at normal n.
  struct Kind {
    const char* name;
    LightmapKind kind;
    std::vector<Image> layers;
    std::vector<float> weights;
  };
  const vec3 b[3] = {{0.816496581f, 0.0f, 0.577350269f},
                     {-0.408248290f, 0.707106781f, 0.577350269f},
                     {-0.408248290f, -0.707106781f, 0.577350269f}};
  float w[3], sum = 0.0f;
  for (int i = 0; i < 3; ++i) {
    w[i] = std::max(glm::dot(n, b[i]), 0.0f);
    w[i] *= w[i];
    sum += w[i];
  }
  const float sh1 = (2.0f / 3.0f) * 0.488603f;
  // Dominant: one direction over the whole map (half floats, so what the GPU reads), which
  // makes A + C·max(0, n·d) linear in the A and C layers with weights 1 and max(0, n·d).
  Image direction(kMapW, kMapH, 3);
  const vec3 d_wanted = glm::normalize(vec3(0.3f, -0.2f, 0.9f));
  vec3 d;
  for (int k = 0; k < 3; ++k) d[k] = glm::unpackHalf1x16(glm::packHalf1x16(d_wanted[k]));
  for (int y = 0; y < kMapH; ++y)
    for (int x = 0; x < kMapW; ++x) direction.set_rgb(x, y, d);
  const std::vector<Kind> kinds = {
      {"plain", LightmapKind::kPlain, {random_layer(0.2f, 1.2f, 1)}, {n.z}},
      {"RNM",
       LightmapKind::kRnm,
       {random_layer(0.2f, 1.2f, 2), random_layer(0.2f, 1.2f, 3), random_layer(0.2f, 1.2f, 4)},
       {w[0] / sum, w[1] / sum, w[2] / sum}},
      {"SH-L1",
       LightmapKind::kShL1,
       {random_layer(0.5f, 1.5f, 5), random_layer(-0.3f, 0.3f, 6), random_layer(-0.3f, 0.3f, 7),
        random_layer(-0.3f, 0.3f, 8)},
       {0.282095f, sh1 * n.y, sh1 * n.z, sh1 * n.x}},
      {"dominant",
       LightmapKind::kDominant,
       {random_layer(0.1f, 0.6f, 9), random_layer(0.2f, 1.2f, 10), direction},
       {1.0f, std::max(glm::dot(n, d), 0.0f), 0.0f}}};
  for (const Kind& kind : kinds) {
    renderer.set_lightmap({kind.kind, kind.layers});
    renderer.render(*scene.camera);
    const Image frame = renderer.hdr();
    // Tolerance: each layer's filter bound times its weight's magnitude, plus fp16 output
    // rounding and float shading (2⁻¹⁰ of the value).
    float filter = 0.0f;
    for (size_t l = 0; l < kind.layers.size(); ++l)
      filter += std::abs(kind.weights[l]) * filter_error(kind.layers[l]);
    size_t outside = 0;
    double worst = 0.0;
    for (int y = 0; y < kFrame; ++y)
      for (int x = 0; x < kFrame; ++x) {
        const Ray ray = scene.camera->generate_ray(x + 0.5f, y + 0.5f, kFrame, kFrame);
        const vec3 p = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
        ASSERT_LT(std::max(std::abs(p.x), std::abs(p.y)), 1.0f) << "the quad must fill the frame";
        Color e(0.0f);
        for (size_t l = 0; l < kind.layers.size(); ++l)
          e += kind.weights[l] * bilinear_clamped(kind.layers[l], uv1_at(p.x, p.y));
        const Color expected = albedo * glm::max(e, Color(0.0f));
        const Color got = frame.rgb(x, y);
        for (int k = 0; k < 3; ++k) {
          const double allowed = albedo[k] * filter + std::ldexp(std::abs(expected[k]), -10);
          const double ratio = std::abs(double(got[k]) - expected[k]) / allowed;
          worst = std::max(worst, ratio);
          outside += ratio > 1.0 ? 1 : 0;
        }
      }
    std::printf(
        "light-map %-6s per pixel: %zu of %d values outside the tolerance, worst %.3f of it\n",
        kind.name, outside, 3 * kFrame * kFrame, worst);
    EXPECT_EQ(outside, 0u) << kind.name;
  }
  EXPECT_EQ(context().validation_message_count(), messages_before);
}

}  // namespace
}  // namespace illum::realtime
