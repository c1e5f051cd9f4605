// glTF 2.0 round trip: the test writes a small .gltf (embedded base64 buffer) and the same
// asset as .glb, with node transforms, several component types, punctual lights, a camera
// and the material extensions illum reads, then checks what the loader made of it.
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf_asset.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/scene/load.h"
#include "test_util.h"

namespace illum {
namespace {

using test::Asset;
using test::contains;
using test::make_asset;
using test::TempDir;
using test::write_glb;
using test::write_gltf;

const Material& material(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return m;
  ADD_FAILURE() << "no material " << name;
  return s.materials.at(0);
}

// Normal-incidence reflectance of a conductor with complex index η + ik.
float conductor_f0(float eta, float k) {
  return ((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k);
}

void check_asset(const Scene& scene) {
  EXPECT_EQ(scene.triangle_count(), 4u);  // quad 2 + two single triangles
  ASSERT_EQ(scene.instances.size(), 3u);
  // The points primitive is skipped with one warning.
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_TRUE(contains(scene.warnings[0], "mode 0")) << scene.warnings[0];

  // Node hierarchy: world = T(1,0,0) · S(2) · Ry(90°) for the quad.
  const Instance& quad = scene.instances[0];
  EXPECT_EQ(quad.name, "quad_node");
  const vec3 p = vec3(quad.transform * vec4(1, 0, 0, 1));
  EXPECT_NEAR(p.x, 1.0f, 1e-5f);
  EXPECT_NEAR(p.y, 0.0f, 1e-5f);
  EXPECT_NEAR(p.z, -2.0f, 1e-5f);
  const Instance& pair = scene.instances[1];
  EXPECT_NEAR(pair.transform[3].z, -3.0f, 1e-6f);
  const Bounds3 b = scene.bounds();
  EXPECT_NEAR(b.max.y, 2.0f, 1e-5f);
  EXPECT_NEAR(b.min.z, -3.0f, 1e-5f);

  // Quad: object-space normal +z from the shared vertices, uvs, tangents along +u = +x.
  const Mesh& qm = scene.meshes[quad.mesh];
  ASSERT_EQ(qm.normals.size(), 4u);
  for (const vec3& n : qm.normals) EXPECT_NEAR(n.z, 1.0f, 1e-5f);
  ASSERT_EQ(qm.tangents.size(), 4u);
  EXPECT_NEAR(qm.tangents[0].x, 1.0f, 1e-5f);
  // Normalized unsigned-short uvs of the first 'pair' primitive.
  const Mesh& tri = scene.meshes[pair.mesh];
  ASSERT_EQ(tri.uv0.size(), 3u);
  EXPECT_FLOAT_EQ(tri.uv0[1].x, 1.0f);
  EXPECT_FLOAT_EQ(tri.uv0[2].y, 1.0f);

  const Material& emitter = material(scene, "emitter");
  EXPECT_EQ(emitter.type, MaterialType::kLambert);
  EXPECT_EQ(emitter.emission, Color(4.0f, 2.0f, 1.0f));
  const Material& glass = material(scene, "glass");
  EXPECT_EQ(glass.type, MaterialType::kDielectric);
  EXPECT_NEAR(glass.ior, 1.33f, 1e-6f);
  EXPECT_NEAR(glass.transmittance.r, 0.9f, 1e-6f);
  const Material& gold = material(scene, "gold");
  EXPECT_EQ(gold.type, MaterialType::kConductor);
  EXPECT_NEAR(conductor_f0(gold.eta.g, gold.k.g), 0.766f, 1e-3f);
  EXPECT_NEAR(conductor_f0(gold.eta.b, gold.k.b), 0.336f, 1e-3f);
  EXPECT_NEAR(conductor_f0(gold.eta.r, gold.k.r), 0.99f, 1e-3f);  // clamped below 1
  const Material& plastic = material(scene, "plastic");
  EXPECT_EQ(plastic.type, MaterialType::kBlinn);
  EXPECT_NEAR(plastic.exponent, 2.0f / (0.09f * 0.09f) - 2.0f, 0.1f);

  int spots = 0, points = 0, areas = 0;
  for (const Light& l : scene.lights) {
    if (l.type == LightType::kSpot) {
      ++spots;
      // glTF's 10 cd in W/sr: ÷ 683 lm/W.
      EXPECT_EQ(l.intensity, Color(static_cast<float>(10.0 / 683.0)));
      EXPECT_NEAR(l.cone_half_angle, 0.5f, 1e-6f);
      EXPECT_NEAR(l.range, 7.0f, 1e-6f);
      EXPECT_NEAR(l.position.y, 3.0f, 1e-6f);
      EXPECT_NEAR(l.direction.y, -1.0f, 1e-5f);
    } else if (l.type == LightType::kPoint) {
      ++points;
      EXPECT_EQ(l.intensity, Color(static_cast<float>(3.0 / 683.0), 0.0f, 0.0f));
      EXPECT_EQ(l.position, vec3(2.0f));
    } else if (l.type == LightType::kArea) {
      ++areas;
      EXPECT_EQ(l.instance, 0);
    }
  }
  EXPECT_EQ(spots, 1);
  EXPECT_EQ(points, 1);
  EXPECT_EQ(areas, 1);

  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_EQ(scene.camera->position, vec3(0.0f, 1.0f, 5.0f));
  EXPECT_NEAR(scene.camera->look_at.z, 4.0f, 1e-6f);
  EXPECT_NEAR(scene.camera->fov_y, 0.8f, 1e-6f);
  // aspectRatio 1.5 shapes the image: the default height, the width 1.5 times it.
  EXPECT_EQ(scene.settings.height, 512);
  EXPECT_EQ(scene.settings.width, 768);
}

TEST(Gltf, RoundTripEmbedded) {
  TempDir dir;
  const Scene scene = load_scene(write_gltf(dir, make_asset()));
  EXPECT_EQ(scene.name, "asset");
  check_asset(scene);
}

TEST(Gltf, RoundTripBinary) {
  TempDir dir;
  const Scene scene = load_scene(write_glb(dir, make_asset()));
  check_asset(scene);
}

TEST(Gltf, MissingBufferFile) {
  TempDir dir;
  Asset a = make_asset();
  a.json["buffers"][0]["uri"] = "geometry.bin";
  const std::string path = dir.write("asset.gltf", a.json.dump());
  const std::string message = test::error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, "missing buffer") && contains(message, "geometry.bin") &&
              contains(message, path))
      << message;
}

TEST(Gltf, AccessorPastBufferEnd) {
  TempDir dir;
  Asset a = make_asset();
  a.json["accessors"][0]["count"] = 400;
  const std::string path = write_gltf(dir, a);
  const std::string message = test::error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(Gltf, TexturesDecodedAndMissingOnesAllowed) {
  TempDir dir;
  Image img(2, 1, 3);
  img.set_rgb(0, 0, Color(1.0f, 0.0f, 0.0f));
  img.set_rgb(1, 0, Color(0.5f));  // written as sRGB 8-bit, read back ≈ 0.5 linear
  write_image(dir.file("base.png"), img);
  Asset a = make_asset();
  a.json["images"] = {{{"uri", "base.png"}}, {{"uri", "missing.png"}}};
  a.json["textures"] = {{{"source", 0}}, {{"source", 1}}};
  a.json["materials"][3]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  a.json["materials"][2]["normalTexture"] = {{"index", 1}, {"scale", 0.5}};
  // A missing image is an error (obj_texture_errors_test.cpp), one warning when allowed.
  EXPECT_TRUE(contains(test::error_of([&] { load_scene(write_gltf(dir, a)); }), "missing.png"));
  LoadOptions allow;
  allow.allow_missing_textures = true;
  const Scene scene = load_scene(write_gltf(dir, a), allow);
  const Material& plastic = material(scene, "plastic");
  ASSERT_NE(plastic.albedo_texture, kNoTexture);
  const Texture& tex = scene.textures.at(plastic.albedo_texture);
  EXPECT_TRUE(tex.srgb);
  EXPECT_EQ(tex.image.width(), 2);
  EXPECT_NEAR(tex.image.rgb(0, 0).r, 1.0f, 1e-6f);
  EXPECT_NEAR(tex.image.rgb(1, 0).g, 0.5f, 0.01f);
  const Material& gold = material(scene, "gold");
  EXPECT_EQ(gold.normal_texture, kNoTexture);
  EXPECT_FLOAT_EQ(gold.normal_scale, 0.5f);
  bool warned = false;
  for (const std::string& w : scene.warnings) warned = warned || contains(w, "missing.png");
  EXPECT_TRUE(warned);
  // Without textures requested nothing is decoded.
  LoadOptions options;
  options.load_textures = false;
  const Scene bare = load_scene(dir.file("asset.gltf"), options);
  EXPECT_TRUE(bare.textures.empty());
}

TEST(Gltf, UsedFromSceneFile) {
  TempDir dir;
  write_gltf(dir, make_asset());
  const std::string path = dir.write("s.illum.json", R"({
    "meshes": [{"file": "asset.gltf", "scale": 0.5, "hide": ["pair_node"]}]})");
  const Scene scene = load_scene(path);
  EXPECT_EQ(scene.triangle_count(), 2u);
  // The quad's (1,0,0) corner: 0.5 · (1, 0, −2).
  const Bounds3 b = scene.bounds();
  EXPECT_NEAR(b.min.z, -1.0f, 1e-5f);
  EXPECT_NEAR(b.max.y, 1.0f, 1e-5f);
  // The camera from the glTF is used (scaled), the lights come along.
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_NEAR(scene.camera->position.z, 2.5f, 1e-5f);
  EXPECT_EQ(scene.lights.size(), 3u);
}

// KHR_lights_punctual's definitions: a point light of I candela gives an illuminance of
// I / d² lux at distance d; a directional light's intensity is its illuminance in lux. With
// 683 lm/W, the irradiance illum computes from the loaded light (intensity / d², or the
// irradiance itself) is that illuminance ÷ 683, for every colour channel.
TEST(Gltf, PunctualLightsArePhotometric) {
  TempDir dir;
  Asset a = make_asset();
  a.json["extensions"]["KHR_lights_punctual"]["lights"] = nlohmann::json::array(
      {{{"type", "point"}, {"intensity", 1366}, {"color", {1, 0.5, 0.25}}},
       {{"type", "directional"}, {"intensity", 100000}},
       {{"type", "spot"}, {"intensity", 50}, {"spot", {{"outerConeAngle", 0.4}}}}});
  a.json["nodes"][4]["extensions"]["KHR_lights_punctual"]["light"] = 1;  // "bulb": directional
  a.json["nodes"][3]["extensions"]["KHR_lights_punctual"]["light"] = 2;  // "spot"
  a.json["nodes"].push_back({{"name", "lamp"},
                             {"translation", {0, 4, 0}},
                             {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  a.json["scenes"][0]["nodes"].push_back(a.json["nodes"].size() - 1);
  const Scene scene = load_scene(write_gltf(dir, a));
  int seen = 0;
  for (const Light& l : scene.lights) {
    if (l.type == LightType::kPoint) {
      // 1366 cd at d = 2 m: 341.5 lux, 0.5 W/m² in the red channel (colour scales channels).
      const float d = 2.0f;
      const double lux = 1366.0 / (d * d);
      EXPECT_NEAR(l.intensity.r / (d * d), lux / 683.0, 1e-6);
      EXPECT_NEAR(l.intensity.g / (d * d), 0.5 * lux / 683.0, 1e-6);
      EXPECT_NEAR(l.intensity.b / (d * d), 0.25 * lux / 683.0, 1e-6);
      ++seen;
    } else if (l.type == LightType::kDirectional) {
      EXPECT_NEAR(l.irradiance.g, 100000.0 / 683.0, 1e-3) << "full sun, 10⁵ lux";
      ++seen;
    } else if (l.type == LightType::kSpot) {
      EXPECT_NEAR(l.intensity.b, 50.0 / 683.0, 1e-7) << "a spot's intensity is candela too";
      ++seen;
    }
  }
  EXPECT_EQ(seen, 3);
}

// The camera's aspectRatio sets the image's width from the height; a ratio that makes the
// image wider than the commands accept is refused with one line.
TEST(Gltf, CameraAspectRatioShapesTheImage) {
  TempDir dir;
  Asset a = make_asset();
  a.json["cameras"][0]["perspective"]["aspectRatio"] = 0.5;
  EXPECT_EQ(load_scene(write_gltf(dir, a)).settings.width, 256);
  a.json["cameras"][0]["perspective"].erase("aspectRatio");
  EXPECT_EQ(load_scene(write_gltf(dir, a)).settings.width, 512) << "no ratio: the default";
  a.json["cameras"][0]["perspective"]["aspectRatio"] = 1000.0;
  try {
    load_scene(write_gltf(dir, a));
    ADD_FAILURE() << "an image 512000 pixels wide was accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "aspectRatio")) << e.what();
  }
}

}  // namespace
}  // namespace illum
