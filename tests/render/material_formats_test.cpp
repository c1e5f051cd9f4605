// How the scene formats carry rough conductors and dielectrics (docs/scene-format.md):
// scene-file `metal` and `alpha`, glTF roughness² → α for metallic and transmissive
// materials, and the errors for a wrong metal, a contradicting type or α outside [0, 1].
#include <gtest/gtest.h>

#include <cmath>

#include "../scene/gltf_asset.h"
#include "../scene/test_util.h"
#include "illum/render/bsdf.h"
#include "illum/scene/load.h"
#include "illum/scene/metals.h"

namespace illum {
namespace {

using test::contains;
using test::error_of;
using test::TempDir;

const Material& material(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return m;
  throw std::runtime_error("no material " + name);
}

std::string scene_with(const TempDir& dir, const std::string& materials) {
  dir.write("box.mtl", "newmtl a\nKd 0.5 0.5 0.5\nnewmtl b\nKd 0.5 0.5 0.5\n");
  dir.write("box.obj",
            "mtllib box.mtl\no t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl a\nf 1 2 3\n"
            "usemtl b\nf 1 2 4\n");
  return dir.write("s.illum.json",
                   R"({"meshes": [{"file": "box.obj"}], "materials": {)" + materials + "}}");
}

TEST(MaterialFormats, SceneFileNamedMetalAndAlpha) {
  TempDir dir;
  const Scene s = load_scene(scene_with(dir, R"("a": {"metal": "copper", "alpha": 0.2},
              "b": {"type": "dielectric", "ior": 1.5, "alpha": 0.09, "roughness": 0.5})"));
  const Material& a = material(s, "a");
  const auto copper = named_metal("copper");
  EXPECT_EQ(a.type, MaterialType::kConductor);
  EXPECT_EQ(a.eta, copper->eta);
  EXPECT_EQ(a.k, copper->k);
  EXPECT_FLOAT_EQ(a.alpha, 0.2f);
  EXPECT_NEAR(a.roughness, std::sqrt(0.2f), 1e-6f);  // real-time roughness follows α
  EXPECT_FALSE(a.is_specular());
  const Material& b = material(s, "b");
  EXPECT_EQ(b.type, MaterialType::kDielectric);
  EXPECT_FLOAT_EQ(b.alpha, 0.09f);
  EXPECT_FLOAT_EQ(b.roughness, 0.5f);  // given: kept
  EXPECT_FALSE(b.is_specular());
  EXPECT_FALSE(Bsdf(b, Color(1.0f), Frame(), vec3(0, 0, 1)).is_delta());
  // Without alpha, conductors and dielectrics stay smooth (delta lobes).
  const Scene smooth = load_scene(scene_with(dir, R"("a": {"metal": "gold"})"));
  EXPECT_EQ(material(smooth, "a").alpha, 0.0f);
  EXPECT_TRUE(material(smooth, "a").is_specular());
}

TEST(MaterialFormats, SceneFileErrorsNameTheKey) {
  TempDir dir;
  std::string e = error_of([&] { load_scene(scene_with(dir, R"("a": {"metal": "brass"})")); });
  EXPECT_TRUE(contains(e, "materials.a.metal") && contains(e, "brass") &&
              contains(e, "gold, copper, silver, aluminium"))
      << e;
  e = error_of(
      [&] { load_scene(scene_with(dir, R"("a": {"type": "lambert", "metal": "gold"})")); });
  EXPECT_TRUE(contains(e, "materials.a.metal") && contains(e, "lambert")) << e;
  e = error_of([&] { load_scene(scene_with(dir, R"("a": {"type": "conductor", "alpha": 1.5})")); });
  EXPECT_TRUE(contains(e, "materials.a.alpha")) << e;
  e = error_of(
      [&] { load_scene(scene_with(dir, R"("a": {"type": "conductor", "alpha": -0.1})")); });
  EXPECT_TRUE(contains(e, "materials.a.alpha")) << e;
}

TEST(MaterialFormats, GltfRoughnessSquaredIsAlpha) {
  TempDir dir;
  const Scene s = load_scene(test::write_gltf(dir, test::make_asset()));
  const Material& gold = material(s, "gold");  // metallic, roughnessFactor 0.2
  EXPECT_EQ(gold.type, MaterialType::kConductor);
  EXPECT_NEAR(gold.alpha, 0.04f, 1e-6f);
  const Material& glass = material(s, "glass");  // transmission, roughnessFactor 0
  EXPECT_EQ(glass.type, MaterialType::kDielectric);
  EXPECT_EQ(glass.alpha, 0.0f);
  EXPECT_TRUE(glass.is_specular());
  EXPECT_EQ(material(s, "plastic").alpha, 0.0f);  // Blinn: α is not its parameter
}

// The built-in `envroom`: mirror, smooth glass and rough copper as its README says, lit by a
// sun and a constant sky.
TEST(MaterialFormats, EnvroomScene) {
  const Scene s = load_scene("envroom");
  EXPECT_EQ(material(s, "mirror").type, MaterialType::kMirror);
  EXPECT_EQ(material(s, "glass").type, MaterialType::kDielectric);
  EXPECT_TRUE(material(s, "glass").is_specular());
  const Material& copper = material(s, "copper");
  EXPECT_EQ(copper.type, MaterialType::kConductor);
  EXPECT_EQ(copper.eta, named_metal("copper")->eta);
  EXPECT_FLOAT_EQ(copper.alpha, 0.2f);
  int suns = 0, environments = 0;
  for (const Light& l : s.lights) {
    suns += l.type == LightType::kDirectional;
    environments += l.type == LightType::kEnvironment;
  }
  EXPECT_EQ(suns, 1);
  EXPECT_EQ(environments, 1);
}

}  // namespace
}  // namespace illum
