// docs/scene-format.md's mappings, each checked on a small file written here: the MTL → material
// table, OBJ conventions (one mesh per object and material, default material, flipped v), the
// scene file's transform order, comments, defaults and light units, and the glTF material and
// light rules the glTF round trip (gltf_test.cpp) does not reach.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "gltf_asset.h"
#include "illum/core/image.h"
#include "illum/scene/load.h"
#include "test_util.h"

namespace illum {
namespace {

using test::contains;
using test::error_of;
using test::TempDir;

const Material& material(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return m;
  ADD_FAILURE() << "no material " << name;
  return s.materials.at(0);
}

const Mesh& mesh_of_material(const Scene& s, const std::string& name) {
  for (const Mesh& m : s.meshes)
    if (s.materials[static_cast<size_t>(m.material)].name == name) return m;
  ADD_FAILURE() << "no mesh with material " << name;
  return s.meshes.at(0);
}

void expect_color(const Color& c, float r, float g, float b, const std::string& what) {
  EXPECT_NEAR(c.r, r, 1e-6f) << what;
  EXPECT_NEAR(c.g, g, 1e-6f) << what;
  EXPECT_NEAR(c.b, b, 1e-6f) << what;
}

// One triangle per material, each in its own object.
std::string obj_using(const std::vector<std::string>& materials) {
  std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
  for (const std::string& m : materials) obj += "o " + m + "\nusemtl " + m + "\nf 1/1 2/2 3/3\n";
  return obj;
}

// scene-format.md, OBJ / MTL: the table row by row.
TEST(FormatMapping, MtlTable) {
  TempDir dir;
  write_image(dir.file("a.png"), Image(2, 2, 3, 0.5f));
  write_image(dir.file("e.png"), Image(2, 2, 3, 0.5f));
  write_image(dir.file("n.png"), Image(2, 2, 3, 0.5f));
  write_image(dir.file("b.png"), Image(2, 2, 3, 0.5f));
  dir.write("m.mtl",
            "newmtl kd\nKd 0.5 0.4 0.3\nmap_Kd a.png\n"
            "newmtl ke\nKd 0.5 0.5 0.5\nKe 2 3 4\n"
            "newmtl ketex\nKd 0.5 0.5 0.5\nmap_Ke e.png\n"
            "newmtl phong\nKd 0.5 0.5 0.5\nKs 0.2 0.3 0.4\nNs 50\nillum 2\n"
            "newmtl mirror3\nKd 0.5 0.5 0.5\nKs 0.9 0.8 0.7\nillum 3\n"
            "newmtl mirror5\nKd 0.5 0.5 0.5\nKs 0.6 0.6 0.6\nillum 5\n"
            "newmtl mirrorks\nKd 0 0 0\nKs 0.7 0.7 0.7\n"
            "newmtl glass7\nKd 0.5 0.5 0.5\nillum 7\n"
            "newmtl glassni\nKd 0.5 0.5 0.5\nNi 1.33\nTf 0.9 0.8 0.7\n"
            "newmtl norm\nKd 0.5 0.5 0.5\nnorm -bm 0.5 n.png\nbump b.png\n"
            "newmtl bump\nKd 0.5 0.5 0.5\nmap_bump -bm 0.25 b.png\n"
            "newmtl dissolve\nKd 0.5 0.5 0.5\nd 0.25\n");
  const Scene s = load_scene(
      dir.write("t.obj", obj_using({"kd", "ke", "ketex", "phong", "mirror3", "mirror5", "mirrorks",
                                    "glass7", "glassni", "norm", "bump", "dissolve"})));
  const auto texture = [&](int id) -> const Texture& {
    return s.textures.at(static_cast<size_t>(id));
  };

  const Material& kd = material(s, "kd");  // Kd → albedo, map_Kd → albedo_texture (sRGB)
  EXPECT_EQ(kd.type, MaterialType::kLambert);
  expect_color(kd.albedo, 0.5f, 0.4f, 0.3f, "Kd");
  ASSERT_NE(kd.albedo_texture, kNoTexture);
  EXPECT_TRUE(contains(texture(kd.albedo_texture).path, "a.png"));
  EXPECT_TRUE(texture(kd.albedo_texture).srgb);

  expect_color(material(s, "ke").emission, 2, 3, 4, "Ke");  // Ke → emission
  const Material& ketex = material(s, "ketex");             // map_Ke without Ke: emission 1
  ASSERT_NE(ketex.emission_texture, kNoTexture);
  EXPECT_TRUE(texture(ketex.emission_texture).srgb);
  expect_color(ketex.emission, 1, 1, 1, "map_Ke without Ke");

  const Material& phong = material(s, "phong");  // Ks > 0 with Kd > 0, Ns
  EXPECT_EQ(phong.type, MaterialType::kPhong);
  expect_color(phong.specular, 0.2f, 0.3f, 0.4f, "Ks");
  EXPECT_EQ(phong.exponent, 50.0f);
  EXPECT_NEAR(phong.roughness, std::sqrt(2.0f / 52.0f), 1e-6f);

  for (const char* name : {"mirror3", "mirror5", "mirrorks"})  // illum 3/5, or Ks with Kd = 0
    EXPECT_EQ(material(s, name).type, MaterialType::kMirror) << name;
  expect_color(material(s, "mirror3").specular, 0.9f, 0.8f, 0.7f, "mirror specular = Ks");
  expect_color(material(s, "mirrorks").specular, 0.7f, 0.7f, 0.7f, "mirror specular = Ks");

  const Material& glass7 = material(s, "glass7");  // illum 7 without Ni/Tf: 1.5, 1
  EXPECT_EQ(glass7.type, MaterialType::kDielectric);
  EXPECT_EQ(glass7.ior, 1.5f);
  expect_color(glass7.transmittance, 1, 1, 1, "illum 7 without Tf");
  const Material& glassni = material(s, "glassni");  // Ni ≠ 1 with Tf > 0
  EXPECT_EQ(glassni.type, MaterialType::kDielectric);
  EXPECT_NEAR(glassni.ior, 1.33f, 1e-6f);
  expect_color(glassni.transmittance, 0.9f, 0.8f, 0.7f, "Tf");

  const Material& norm = material(s, "norm");  // norm wins over bump; -bm → normal_scale
  ASSERT_NE(norm.normal_texture, kNoTexture);
  EXPECT_TRUE(contains(texture(norm.normal_texture).path, "n.png"));
  EXPECT_FALSE(texture(norm.normal_texture).srgb);
  EXPECT_EQ(norm.normal_scale, 0.5f);
  const Material& bump = material(s, "bump");  // else map_bump
  ASSERT_NE(bump.normal_texture, kNoTexture);
  EXPECT_TRUE(contains(texture(bump.normal_texture).path, "b.png"));
  EXPECT_EQ(bump.normal_scale, 0.25f);

  EXPECT_EQ(material(s, "dissolve").opacity, 0.25f);  // d → opacity
}

// scene-format.md, OBJ / MTL: one mesh per (object, material), one instance named after the
// object, faces without usemtl get a white-ish Lambert `default`, and vt's v is flipped.
TEST(FormatMapping, ObjMeshesDefaultMaterialAndFlippedV) {
  TempDir dir;
  dir.write("m.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n");
  const Scene s = load_scene(dir.write("t.obj",
                                       "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                       "vt 0 0.25\nvt 1 0\nvt 0 1\n"
                                       "o plain\nf 1/1 2/2 3/3\n"
                                       "o two\nusemtl red\nf 1/1 2/2 3/3\n"
                                       "usemtl blue\nf 1/1 3/3 2/2\n"));
  ASSERT_EQ(s.meshes.size(), 3u);
  int two = 0;
  for (const Instance& i : s.instances) two += i.name == "two";
  EXPECT_EQ(two, 2) << "one instance per mesh, named after the object";
  const Material& def = material(s, "default");
  EXPECT_EQ(def.type, MaterialType::kLambert);
  EXPECT_GE(std::min({def.albedo.r, def.albedo.g, def.albedo.b}), 0.5f) << "white-ish";
  EXPECT_EQ(def.albedo.r, def.albedo.g);
  EXPECT_EQ(def.albedo.g, def.albedo.b);
  const Mesh& red = mesh_of_material(s, "red");
  ASSERT_EQ(red.uv0.size(), 3u);
  EXPECT_NEAR(red.uv0[0].y, 0.75f, 1e-6f) << "vt v = 0.25 is 0.75 from the top";
  EXPECT_NEAR(red.uv0[2].y, 0.0f, 1e-6f);
}

// scene-format.md, illum scene files: p' = T · Rz · Ry · Rx · S · scale · p, comments allowed,
// name defaults to the file name, colour defaults to white, spot I = Φ/Ω.
TEST(FormatMapping, SceneFileTransformCommentsAndDefaults) {
  TempDir dir;
  dir.write("tri.obj", "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("my-room.illum.json", R"({
    // a line comment
    "meshes": [{"file": "tri.obj", "scale": 2, /* a block comment */
                "transform": {"translate": [10, 20, 30], "rotate_deg": [90, 90, 0],
                              "scale": [1, 3, 5]}}],
    "lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0],
                "half_angle_deg": 25, "flux": 100}]
  })"));
  EXPECT_EQ(s.name, "my-room");
  // (1,0,0): scale → (2,0,0), S → (2,0,0), Rx(90°) → (2,0,0), Ry(90°) → (0,0,−2), + T.
  // (0,1,0): → (0,2,0) → (0,6,0) → Rx(90°): (0,0,6) → Ry(90°): (6,0,0) → + T.
  // Any other order of the rotations or of S and scale moves these points.
  const Mesh& m = s.meshes.at(0);
  const mat4& t = s.instances.at(0).transform;
  const auto world = [&](size_t v) { return vec3(t * vec4(m.positions.at(v), 1.0f)); };
  const vec3 a = world(1), b = world(2);
  EXPECT_NEAR(a.x, 10.0f, 1e-4f);
  EXPECT_NEAR(a.y, 20.0f, 1e-4f);
  EXPECT_NEAR(a.z, 28.0f, 1e-4f);
  EXPECT_NEAR(b.x, 16.0f, 1e-4f);
  EXPECT_NEAR(b.y, 20.0f, 1e-4f);
  EXPECT_NEAR(b.z, 30.0f, 1e-4f);
  ASSERT_EQ(s.lights.size(), 1u);
  const float omega = 2.0f * kPi * (1.0f - std::cos(radians(25.0f)));
  expect_color(s.lights[0].intensity, 100.0f / omega, 100.0f / omega, 100.0f / omega,
               "spot I = Φ/Ω, colour white by default");
  // Point and spot lights need exactly one of flux and intensity: neither is an error too.
  const std::string neither = dir.write(
      "neither.illum.json",
      R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "point", "position": [0, 1, 0]}]})");
  const std::string message = error_of([&] { load_scene(neither); });
  EXPECT_TRUE(contains(message, "neither.illum.json") && contains(message, "lights[0]")) << message;
}

// scene-format.md, glTF 2.0 materials and KHR_lights_punctual: a glossy dielectric is Blinn
// with specular 0.04 and an exponent capped at 10⁴; base colour alpha → opacity; a
// directional light's intensity is its illuminance in lux, irradiance × 683 lm/W.
TEST(FormatMapping, GltfGlossyDielectricOpacityAndSun) {
  TempDir dir;
  test::Asset a = test::make_asset();
  auto& plastic = a.json["materials"][3]["pbrMetallicRoughness"];
  plastic["roughnessFactor"] = 0.0;
  plastic["baseColorFactor"] = {0.2, 0.3, 0.8, 0.25};
  a.json["extensions"]["KHR_lights_punctual"]["lights"].push_back(
      {{"type", "directional"}, {"intensity", 5 * 683}, {"color", {1, 0.5, 0.25}}});
  a.json["nodes"].push_back({{"name", "sun"},
                             {"rotation", {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)}},
                             {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  a.json["scenes"][0]["nodes"].push_back(a.json["nodes"].size() - 1);
  const Scene s = load_scene(test::write_gltf(dir, a));
  const Material& glossy = material(s, "plastic");
  EXPECT_EQ(glossy.type, MaterialType::kBlinn);
  expect_color(glossy.specular, 0.04f, 0.04f, 0.04f, "glTF's dielectric F0");
  EXPECT_EQ(glossy.exponent, 1e4f) << "roughness 0: n = 2/α² − 2 capped at 10⁴";
  EXPECT_EQ(glossy.opacity, 0.25f);
  int suns = 0;
  for (const Light& l : s.lights) {
    if (l.type != LightType::kDirectional) continue;
    ++suns;
    expect_color(l.irradiance, 5.0f, 2.5f, 1.25f, "3415 lux at 683 lm/W is 5 W/m²");
    // −z of a node turned −90° about x points down.
    EXPECT_NEAR(l.direction.y, -1.0f, 1e-5f);
  }
  EXPECT_EQ(suns, 1);
}

// scene-format.md, glTF 2.0: "Sparse accessors are rejected"; an orthographic camera needs
// xmag, ymag ≠ 0 and 0 ≤ znear < zfar (perspective cameras: GltfErrors.LightAndCameraValues).
TEST(FormatMapping, GltfSparseAccessorsAndOrthographicCameras) {
  TempDir dir;
  test::Asset sparse = test::make_asset();
  sparse.json["accessors"][0]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", 0}, {"componentType", 5121}}},
      {"values", {{"bufferView", 0}}}};
  const std::string s1 = test::write_gltf(dir, sparse, "sparse.gltf");
  const std::string m1 = error_of([&] { load_scene(s1); });
  EXPECT_TRUE(contains(m1, "sparse.gltf") && contains(m1, "accessors[0]") && contains(m1, "sparse"))
      << m1;
  const auto with_camera = [&](const nlohmann::json& ortho, const std::string& name) {
    test::Asset a = test::make_asset();
    a.json["cameras"].push_back({{"type", "orthographic"}, {"orthographic", ortho}});
    return test::write_gltf(dir, a, name);
  };
  const std::string flat =
      with_camera({{"xmag", 0}, {"ymag", 1}, {"znear", 0}, {"zfar", 10}}, "flat.gltf");
  const std::string m2 = error_of([&] { load_scene(flat); });
  EXPECT_TRUE(contains(m2, "flat.gltf") && contains(m2, "cameras[1] xmag and ymag")) << m2;
  const std::string inverted =
      with_camera({{"xmag", 1}, {"ymag", 1}, {"znear", 5}, {"zfar", 1}}, "inverted.gltf");
  const std::string m3 = error_of([&] { load_scene(inverted); });
  EXPECT_TRUE(contains(m3, "inverted.gltf") && contains(m3, "cameras[1] needs 0 ≤ znear < zfar"))
      << m3;
  EXPECT_NO_THROW(
      load_scene(with_camera({{"xmag", 1}, {"ymag", 1}, {"znear", 0}, {"zfar", 10}}, "fine.gltf")));
}

// scene-format.md, Rules: "Lights and cameras that come from a glTF file are transformed with
// its meshes. The first camera found wins: the scene file's camera, else the first glTF
// camera." "A mesh used by a single instance gets its whole transform baked into its
// vertices (the instance transform becomes identity); meshes instanced several times keep
// their transforms." glTF: "glTF meshes used by several nodes are shared".
TEST(FormatMapping, GltfThroughASceneFileInstancesLightsAndCamera) {
  TempDir dir;
  test::Asset a = test::make_asset();
  a.json["nodes"].push_back({{"name", "quad_again"}, {"mesh", 0}, {"translation", {0, 0, 7}}});
  a.json["scenes"][0]["nodes"].push_back(a.json["nodes"].size() - 1);
  test::write_gltf(dir, a);
  const Scene scaled = load_scene(
      dir.write("scaled.illum.json", R"({"meshes": [{"file": "asset.gltf", "scale": 0.5}]})"));
  int points = 0;
  for (const Light& l : scaled.lights) {
    if (l.type != LightType::kPoint) continue;
    ++points;
    EXPECT_NEAR(l.position.x, 1.0f, 1e-5f) << "the bulb at (2, 2, 2), scaled by 0.5";
    EXPECT_NEAR(l.position.y, 1.0f, 1e-5f);
    EXPECT_NEAR(l.position.z, 1.0f, 1e-5f);
  }
  EXPECT_EQ(points, 1);
  ASSERT_TRUE(scaled.camera.has_value());
  EXPECT_NEAR(scaled.camera->position.y, 0.5f, 1e-5f) << "the glTF camera, scaled";
  // The quad (mesh 0) is used by two nodes: one shared mesh, two instances with their own
  // transforms; the single-use triangle mesh has its transform in its vertices.
  int quad_instances = 0, identity_instances = 0;
  size_t quad_mesh = scaled.meshes.size();
  for (const Instance& i : scaled.instances) {
    const bool identity = i.transform == mat4(1.0f);
    identity_instances += identity;
    if (i.name == "quad_node" || i.name == "quad_again") {
      ++quad_instances;
      EXPECT_FALSE(identity) << i.name;
      if (quad_mesh == scaled.meshes.size()) quad_mesh = i.mesh;
      EXPECT_EQ(i.mesh, quad_mesh) << "one shared mesh";
    }
  }
  EXPECT_EQ(quad_instances, 2);
  EXPECT_GE(identity_instances, 1) << "the meshes used once are baked";

  const Scene own = load_scene(dir.write("own.illum.json", R"({
    "meshes": [{"file": "asset.gltf"}],
    "camera": {"position": [9, 9, 9], "look_at": [0, 0, 0], "fov_y_deg": 30}})"));
  ASSERT_TRUE(own.camera.has_value());
  EXPECT_EQ(own.camera->position, vec3(9.0f)) << "the scene file's camera wins";
}

// scene-format.md, Rules: the environment is "exactly one of `file` ... or `constant`", and an
// environment map's texels must be "finite ... and not negative"; "(any `*.json`)" is a
// scene file.
TEST(FormatMapping, SceneFileEnvironmentRules) {
  TempDir dir;
  dir.write("tri.obj", "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  Image sky(8, 4, 3, 0.5f);
  write_image(dir.file("sky.exr"), sky);
  sky.set_rgb(3, 2, Color(0.5f, -0.25f, 0.5f));
  write_image(dir.file("negative.exr"), sky);
  const auto scene_with = [&](const std::string& name, const std::string& environment) {
    return dir.write(name,
                     R"({"meshes": [{"file": "tri.obj"}], "environment": )" + environment + "}");
  };
  for (const char* env : {R"({"file": "sky.exr", "constant": [1, 1, 1]})", R"({"scale": 2})"}) {
    const std::string path = scene_with("env.illum.json", env);
    const std::string m = error_of([&] { load_scene(path); });
    EXPECT_TRUE(contains(m, "env.illum.json") && contains(m, "exactly one of 'file' or 'constant'"))
        << env << ": " << m;
  }
  const std::string negative = scene_with("neg.json", R"({"file": "negative.exr"})");
  const std::string m = error_of([&] { load_scene(negative); });
  EXPECT_TRUE(contains(m, "negative.exr") && contains(m, "negative value at texel (3, 2)")) << m;
  const Scene fine = load_scene(scene_with("fine.json", R"({"file": "sky.exr", "scale": 2})"));
  ASSERT_TRUE(fine.environment.has_value());
  EXPECT_EQ(fine.environment->scale, 2.0f);
}

}  // namespace
}  // namespace illum
