// The glTF export (export/lightmap_export.h) read back through the project's own loader:
// the same uv1 on every triangle corner (bit for bit: float bits are copied), the RGBM PNG
// decoding to the folder's texels within RGBM's quantisation bound, MSFT_lightmap on every
// material pointing at that texture, the EXR beside it equal to the exported layer; RNM and
// SH-L1 folders reduced to the irradiance at the normal; lights, camera and transforms
// surviving the round trip; a refused or failed export leaving nothing behind.
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "illum/atlas/atlas.h"
#include "illum/core/error.h"
#include "illum/core/hdr_encoding.h"
#include "illum/core/histogram_tone.h"
#include "illum/core/sh.h"
#include "illum/export/lightmap_export.h"
#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"

namespace illum::exporter {
namespace {

namespace fs = std::filesystem;

// The JSON chunk and the BIN chunk of a GLB file (the test's own reading, not tinygltf's).
struct Glb {
  nlohmann::json json;
  std::vector<uint8_t> bin;
};

Glb read_glb(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  auto u32 = [&](size_t at) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  Glb glb;
  EXPECT_GE(bytes.size(), 20u);
  EXPECT_EQ(u32(0), 0x46546C67u);  // "glTF"
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), bytes.size());
  const uint32_t json_length = u32(12);
  glb.json = nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + json_length);
  const size_t bin_at = 20 + json_length;
  if (bin_at + 8 <= bytes.size())
    glb.bin.assign(bytes.begin() + bin_at + 8, bytes.begin() + bin_at + 8 + u32(bin_at));
  return glb;
}

// The light-map image's RGBA bytes, found through the materials' MSFT_lightmap reference.
std::vector<uint8_t> lightmap_bytes(const Glb& glb, int texture, int* width, int* height) {
  const int image = glb.json.at("textures").at(texture).at("source");
  const nlohmann::json& view =
      glb.json.at("bufferViews").at(glb.json.at("images").at(image).at("bufferView").get<int>());
  const size_t offset = view.value("byteOffset", 0), length = view.at("byteLength");
  const std::span<const uint8_t> png(glb.bin.data() + offset, length);
  const Image decoded = decode_image(png, "lightmap", /*srgb=*/false);  // value / 255
  EXPECT_EQ(decoded.channels(), 4);
  *width = decoded.width();
  *height = decoded.height();
  std::vector<uint8_t> bytes(decoded.data().size());
  for (size_t k = 0; k < bytes.size(); ++k)
    bytes[k] = static_cast<uint8_t>(std::lround(decoded.data()[k] * 255.0f));
  return bytes;
}

// RGBM's bound, derived here (not taken from hdr_encoding): a texel whose largest channel is
// L < M gets the multiplier a = ⌈255·L/M⌉ ≤ 255·L/M + 1, each channel is rounded to the
// nearest of 255 steps of a/255·M, so its error is at most half a step,
// 0.5/255 · (L/M + 1/255) · M; plus float rounding of the products (10⁻⁶·M).
float rgbm_bound(float largest, float range) {
  return 0.5f / 255.0f * (std::min(largest, range) / range + 1.0f / 255.0f) * range + 1e-6f * range;
}

class GltfExport : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("illum_export_{}_{}", info->name(), ::getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    loaded_ = load_scene(ILLUM_DATA_DIR "/scenes/cornell/cornell.illum.json");
    baked_ = loaded_;
    atlas::make_meshes_unique(baked_);
    atlas::AtlasOptions options;
    options.resolution = 64;
    set_.atlas = atlas::build_atlas(baked_, options);
    atlas::apply_atlas(baked_, set_.atlas);
    set_.scene = "cornell";
    set_.scene_triangles = baked_.triangle_count();
    set_.scene_hash = geometry_hash_hex(baked_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // An HDR layer over five decades (10⁻³ … 10^1.5) with black texels and, if `negative`,
  // some negative ones (SH coefficients can be).
  Image layer(int seed, bool negative = false) const {
    Image image(set_.atlas.width, set_.atlas.height, 3);
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x)
        for (int c = 0; c < 3; ++c) {
          const int h = (x * 7 + y * 13 + c * 5 + seed * 31) % 97;
          float v = (x + y + seed) % 11 == 0 ? 0.0f : std::pow(10.0f, -3.0f + 4.5f * h / 96.0f);
          if (negative && h % 5 == 0) v = -v;
          image.pixel(x, y)[c] = v;
        }
    return image;
  }

  LightmapExportResult export_set(const LightmapExportOptions& options = {}) {
    Scene scene = loaded_;
    return export_gltf_with_lightmap(scene, set_, dir_ / "out.glb", options);
  }

  // Decoded RGBM texels against `expected` within rgbm_bound; returns the largest error
  // relative to its bound (≤ 1 passes).
  double check_rgbm(const Glb& glb, int texture, const Image& expected, float range) {
    int width = 0, height = 0;
    const std::vector<uint8_t> bytes = lightmap_bytes(glb, texture, &width, &height);
    EXPECT_EQ(width, expected.width());
    EXPECT_EQ(height, expected.height());
    double worst = 0.0;
    int failures = 0;
    for (int y = 0; y < height && failures < 5; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t at = 4 * (static_cast<size_t>(y) * width + x);
        const Color got =
            decode_rgbm({bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]}, range);
        const Color want = glm::max(expected.rgb(x, y), Color(0.0f));
        const float bound = rgbm_bound(max_component(want), range);
        for (int c = 0; c < 3; ++c) {
          const double ratio = std::abs(got[c] - want[c]) / bound;
          worst = std::max(worst, ratio);
          if (ratio > 1.0 && ++failures <= 5)
            ADD_FAILURE() << "texel (" << x << ", " << y << ") channel " << c << ": " << got[c]
                          << " decoded, " << want[c] << " baked, bound " << bound;
        }
      }
    return worst;
  }

  // The index of the texture every material's MSFT_lightmap names (checked to be one).
  static int lightmap_texture(const Glb& glb) {
    const nlohmann::json& used = glb.json.at("extensionsUsed");
    EXPECT_NE(std::find(used.begin(), used.end(), "MSFT_lightmap"), used.end());
    EXPECT_FALSE(glb.json.contains("extensionsRequired"));
    int texture = -1;
    for (const nlohmann::json& m : glb.json.at("materials")) {
      const nlohmann::json& ext = m.at("extensions").at("MSFT_lightmap");
      EXPECT_EQ(ext.at("lightmapTexture").at("texCoord"), 1);
      const int t = ext.at("lightmapTexture").at("index");
      if (texture < 0) texture = t;
      EXPECT_EQ(t, texture);
    }
    const int image = glb.json.at("textures").at(texture).at("source");
    EXPECT_EQ(glb.json.at("images").at(image).at("name"), "lightmap");
    return texture;
  }

  fs::path dir_;
  Scene loaded_, baked_;
  baked::LightmapSet set_;
};

TEST_F(GltfExport, PlainFolderRoundTripsThroughTheOwnLoader) {
  set_.basis = "plain";
  set_.layers = {layer(1)};
  const LightmapExportResult r = export_set();
  // The project's own loader reads the file: the same geometry bit for bit, uv1 included
  // (its geometry_hash is the one the folder records), and each triangle corner's uv1.
  const Scene back = load_scene((dir_ / "out.glb").string());
  EXPECT_EQ(geometry_hash_hex(back), set_.scene_hash);
  ASSERT_EQ(back.meshes.size(), baked_.meshes.size());
  for (size_t i = 0; i < back.meshes.size(); ++i) {
    const Mesh &got = back.meshes[i], &want = baked_.meshes[i];
    ASSERT_EQ(got.indices.size(), want.indices.size()) << i;
    ASSERT_EQ(got.uv1.size(), got.positions.size()) << i;
    for (size_t k = 0; k < got.indices.size(); ++k) {
      EXPECT_EQ(got.uv1[got.indices[k]], want.uv1[want.indices[k]])
          << "mesh " << i << " corner " << k;
      EXPECT_EQ(got.positions[got.indices[k]], want.positions[want.indices[k]]);
    }
  }
  // MSFT_lightmap on every material, the RGBM texture within RGBM's bound of the folder.
  const Glb glb = read_glb(dir_ / "out.glb");
  const int texture = lightmap_texture(glb);
  const nlohmann::json& extras =
      glb.json.at("materials").at(0).at("extensions").at("MSFT_lightmap").at("extras");
  EXPECT_EQ(extras.at("encoding"), "RGBM");
  const float range = extras.at("range").get<float>();
  float largest = 0.0f;
  for (float v : set_.layers[0].data()) largest = std::max(largest, v);
  EXPECT_EQ(range, largest);  // the default range: nothing clamps
  EXPECT_EQ(r.rgbm_range, largest);
  const double worst = check_rgbm(glb, texture, set_.layers[0], range);
  EXPECT_LE(worst, 1.0);
  EXPECT_GT(worst, 0.3);  // the bound is not loose by orders of magnitude
  // The loader decodes it: every texel is the file's RGBM bytes decoded, and it says what
  // the map is.
  ASSERT_TRUE(back.lightmap.has_value());
  EXPECT_EQ(back.lightmap->encoding, "RGBM");
  EXPECT_EQ(back.lightmap->range, range);
  EXPECT_EQ(back.lightmap->tone, "none");
  EXPECT_EQ(back.lightmap->basis, "plain");
  EXPECT_EQ(back.lightmap->layer, r.layer);
  EXPECT_TRUE(back.textures.empty());  // not a material texture
  int width = 0, height = 0;
  const std::vector<uint8_t> bytes = lightmap_bytes(glb, texture, &width, &height);
  const Image& decoded = back.lightmap->image;
  ASSERT_EQ(decoded.width(), width);
  ASSERT_EQ(decoded.height(), height);
  ASSERT_EQ(decoded.channels(), 3);
  int mismatches = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t at = 4 * (static_cast<size_t>(y) * width + x);
      mismatches += decoded.rgb(x, y) !=
                    decode_rgbm({bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]}, range);
    }
  EXPECT_EQ(mismatches, 0);
  // The EXR beside it is the folder's layer, value for value.
  const Image exr = read_image((dir_ / "out.lightmap.exr").string(), false);
  EXPECT_EQ(exr.data(), set_.layers[0].data());
}

TEST_F(GltfExport, RnmAndShFoldersExportTheIrradianceAtTheNormal) {
  set_.basis = "rnm";
  set_.layers = {layer(1), layer(2), layer(3)};
  export_set();
  Image mean = set_.layers[0];
  for (size_t k = 0; k < mean.data().size(); ++k)
    mean.data()[k] =
        (set_.layers[0].data()[k] + set_.layers[1].data()[k] + set_.layers[2].data()[k]) / 3.0f;
  EXPECT_EQ(read_image((dir_ / "out.lightmap.exr").string(), false).data(), mean.data());
  Glb glb = read_glb(dir_ / "out.glb");
  float range =
      glb.json.at("materials").at(0).at("extensions").at("MSFT_lightmap").at("extras").at("range");
  EXPECT_LE(check_rgbm(glb, lightmap_texture(glb), mean, range), 1.0);

  // SH-L1: E(n)/π = Σ_l (Λ_l/π) c_lm Y_lm(n), Λ_0/π = 1, Λ_1/π = 2/3, at n = z.
  set_.basis = "sh";
  set_.layers = {layer(1), layer(2, true), layer(3, true), layer(4, true)};
  export_set();
  const glm::vec4 y = sh::evaluate_l1(glm::vec3(0.0f, 0.0f, 1.0f));
  Image irradiance = set_.layers[0];
  std::vector<float> magnitude(irradiance.data().size());  // Σ |term|, for the bound below
  for (size_t k = 0; k < irradiance.data().size(); ++k) {
    float e = y.x * set_.layers[0].data()[k];
    magnitude[k] = std::abs(e);
    for (int i = 1; i < 4; ++i) {
      const float term = 2.0f / 3.0f * y[i] * set_.layers[i].data()[k];
      e += term;
      magnitude[k] += std::abs(term);
    }
    irradiance.data()[k] = std::max(e, 0.0f);
  }
  const Image exr = read_image((dir_ / "out.lightmap.exr").string(), false);
  int clamped = 0;
  for (size_t k = 0; k < exr.data().size(); ++k) {
    clamped += irradiance.data()[k] == 0.0f;
    // Two float evaluations of the same 4-term sum (other constants and order): each rounds
    // its products and sums by ε/2 of at most Σ|term| — 8 roundings between them.
    EXPECT_NEAR(exr.data()[k], irradiance.data()[k],
                8 * 0.5f * std::numeric_limits<float>::epsilon() * magnitude[k])
        << k;
  }
  EXPECT_GT(clamped, 0);  // the clamp at 0 is exercised
  glb = read_glb(dir_ / "out.glb");
  range =
      glb.json.at("materials").at(0).at("extensions").at("MSFT_lightmap").at("extras").at("range");
  EXPECT_LE(check_rgbm(glb, lightmap_texture(glb), exr, range), 1.0);
}

// Dominant direction: layers A, C, d; the renderer shows E/π(n) = A + C·max(0, n·d), at
// the unperturbed normal n = z: A + C·max(0, d_z). d is any direction here, half of the
// texels facing away (d_z < 0: the ambient alone).
TEST_F(GltfExport, DominantFolderExportsTheIrradianceAtTheNormal) {
  set_.basis = "dominant";
  set_.layers = {layer(1), layer(2), layer(3, true)};
  export_set();
  Image expected = set_.layers[0];
  int facing_away = 0;
  for (int y = 0; y < expected.height(); ++y)
    for (int x = 0; x < expected.width(); ++x) {
      const float dz = set_.layers[2].rgb(x, y).b;
      facing_away += dz < 0.0f;
      expected.set_rgb(x, y,
                       set_.layers[0].rgb(x, y) + set_.layers[1].rgb(x, y) * std::max(0.0f, dz));
    }
  EXPECT_GT(facing_away, 0);
  EXPECT_EQ(read_image((dir_ / "out.lightmap.exr").string(), false).data(), expected.data());
  Glb glb = read_glb(dir_ / "out.glb");
  const float range =
      glb.json.at("materials").at(0).at("extensions").at("MSFT_lightmap").at("extras").at("range");
  EXPECT_LE(check_rgbm(glb, lightmap_texture(glb), expected, range), 1.0);
}

TEST_F(GltfExport, Lrp97ToneMapsThePngOnlyAndTheExrStaysLinear) {
  set_.basis = "plain";
  set_.layers = {layer(1)};
  LightmapExportOptions options;
  options.tone = "lrp97";
  const LightmapExportResult r = export_set(options);
  EXPECT_EQ(r.rgbm_range, 1.0f);
  const Glb glb = read_glb(dir_ / "out.glb");
  const Image toned = histogram_tone_mapped(set_.layers[0]);
  EXPECT_LE(check_rgbm(glb, lightmap_texture(glb), toned, 1.0f), 1.0);
  EXPECT_EQ(
      glb.json.at("materials").at(0).at("extensions").at("MSFT_lightmap").at("extras").at("tone"),
      "lrp97");
  EXPECT_EQ(read_image((dir_ / "out.lightmap.exr").string(), false).data(), set_.layers[0].data());
}

// Lights, camera and instance transforms read back by the own loader as they were.
TEST_F(GltfExport, LightsCameraAndTransformsRoundTrip) {
  Scene scene;
  scene.name = "lit";
  scene.materials.push_back(Material{});
  Mesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  quad.normals.assign(4, vec3(0, 1, 0));
  quad.indices = {0, 2, 1, 0, 3, 2};
  scene.meshes.push_back(quad);
  Instance instance;
  instance.transform = glm::translate(mat4(1.0f), vec3(0.5f, -1.0f, 2.0f)) *
                       glm::rotate(mat4(1.0f), 0.3f, vec3(0, 1, 0));
  scene.instances.push_back(instance);
  Light point;
  point.type = LightType::kPoint;
  point.position = vec3(0.1f, 2.0f, 0.3f);
  point.intensity = Color(3.0f, 2.0f, 1.0f);
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = vec3(1.0f, 3.0f, -1.0f);
  spot.direction = glm::normalize(vec3(0.2f, -1.0f, 0.1f));
  spot.intensity = Color(5.0f);
  spot.cone_half_angle = 0.4f;
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(vec3(-0.3f, -1.0f, -0.2f));
  sun.irradiance = Color(2.0f, 2.0f, 1.5f);
  scene.lights = {point, spot, sun};
  Camera camera;
  camera.position = vec3(0.5f, 1.0f, 4.0f);
  camera.look_at = vec3(0.5f, 0.0f, 0.5f);
  camera.fov_y = 0.7f;
  scene.camera = camera;
  const std::vector<uint8_t> bytes = scene_to_glb(scene, nullptr);
  std::ofstream(dir_ / "lit.glb", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  const Scene back = load_scene((dir_ / "lit.glb").string());
  ASSERT_EQ(back.instances.size(), 1u);
  EXPECT_EQ(back.instances[0].transform, instance.transform);
  ASSERT_EQ(back.lights.size(), 3u);
  // Analytic bounds in float roundings (each operation rounds by at most ε/2 relative,
  // ε = 2⁻²³): a colour is written as value/largest and read back × largest (2 roundings per
  // channel, then the double → float of the JSON: 3), positions are copied, a direction goes
  // through a normalise, two cross products and the loader's matrix product and normalise
  // (under 8 roundings of a unit vector); the camera's position goes through a 4×4 inverse
  // (cofactors of 3×3 products: allow 64 roundings of the largest coordinate).
  constexpr float kEps = std::numeric_limits<float>::epsilon();
  const auto near = [&](const vec3& got, const vec3& want, float roundings) {
    return glm::length(got - want) <= roundings * 0.5f * kEps * std::max(1.0f, glm::length(want));
  };
  for (size_t i = 0; i < 3; ++i) {
    const Light &got = back.lights[i], &want = scene.lights[i];
    EXPECT_EQ(got.type, want.type) << i;
    EXPECT_TRUE(near(got.intensity, want.intensity, 3 * 1.8f)) << i;  // |Δ| over 3 channels
    EXPECT_TRUE(near(got.irradiance, want.irradiance, 3 * 1.8f)) << i;
    if (want.type != LightType::kDirectional) {
      EXPECT_EQ(got.position, want.position) << i;
    }
    if (want.type != LightType::kPoint) {
      EXPECT_TRUE(near(got.direction, want.direction, 8)) << i;
    }
  }
  EXPECT_EQ(back.lights[1].cone_half_angle, 0.4f);
  ASSERT_TRUE(back.camera.has_value());
  EXPECT_TRUE(near(back.camera->position, camera.position, 64));
  EXPECT_TRUE(near(glm::normalize(back.camera->look_at - back.camera->position),
                   glm::normalize(camera.look_at - camera.position), 8));
  EXPECT_FLOAT_EQ(back.camera->fov_y, 0.7f);
}

// A folder baked for another scene is refused before anything is written, the scene left as
// it was; a write that fails half-way (the EXR's temporary name blocked) leaves neither file
// nor any temporary one.
TEST_F(GltfExport, RefusedOrFailedExportsLeaveNothing) {
  set_.basis = "plain";
  set_.layers = {layer(1)};
  set_.scene_hash = "0123456789abcdef";
  Scene scene = loaded_;
  const uint64_t before = geometry_hash(scene);
  EXPECT_THROW(export_gltf_with_lightmap(scene, set_, dir_ / "out.glb"), Error);
  EXPECT_EQ(geometry_hash(scene), before);
  EXPECT_TRUE(fs::is_empty(dir_));

  set_.scene_hash = geometry_hash_hex(baked_);
  const fs::path blocker = dir_ / fmt::format(".out.lightmap.exr.tmp-{}.exr", ::getpid());
  fs::create_directories(blocker / "inside");
  EXPECT_THROW(export_set(), Error);
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path(), blocker) << "left behind: " << entry.path();
  fs::remove_all(blocker);
  export_set();  // unblocked, it works
  EXPECT_TRUE(fs::exists(dir_ / "out.glb"));
  EXPECT_TRUE(fs::exists(dir_ / "out.lightmap.exr"));
}

}  // namespace
}  // namespace illum::exporter
