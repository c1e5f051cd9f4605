// Bad input: every path gets one clear line naming the file (and key or line), and nothing
// crashes or half-loads. Also the non-fatal findings that become warnings.
#include <string>

#include <gtest/gtest.h>

#include "gltf_asset.h"
#include "illum/core/error.h"
#include "illum/scene/load.h"
#include "test_util.h"

namespace illum {
namespace {

using test::contains;
using test::error_of;
using test::TempDir;

void expect_one_line(const std::string& message) {
  EXPECT_FALSE(message.empty());
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

const char* kTriangleObj =
    "o tri\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
    "f 1 2 3\n";

// A scene file around one triangle with `lights` (a JSON array) and extra top-level text.
std::string scene_json(const std::string& lights, const std::string& extra = "") {
  return std::string(R"({"meshes": [{"file": "tri.obj"}], "lights": )") + lights + extra + "}";
}

TEST(LoadErrors, MissingFile) {
  const std::string message = error_of([] { load_scene("/nonexistent/folder/scene.obj"); });
  EXPECT_TRUE(contains(message, "/nonexistent/folder/scene.obj")) << message;
  EXPECT_TRUE(contains(message, "cannot open")) << message;
  expect_one_line(message);
  for (const char* path :
       {"/nonexistent/a.gltf", "/nonexistent/a.glb", "/nonexistent/a.illum.json"}) {
    const std::string m = error_of([&] { load_scene(path); });
    EXPECT_TRUE(contains(m, "cannot open") && contains(m, path)) << m;
  }
}

TEST(LoadErrors, UnknownNameOrFormat) {
  const std::string message = error_of([] { load_scene("no_such_scene"); });
  EXPECT_TRUE(contains(message, "no_such_scene")) << message;
  EXPECT_TRUE(contains(message, "cornell")) << message;  // lists the built-in names
  TempDir dir;
  const std::string path = dir.write("scene.ply", "ply\n");
  const std::string m = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(m, "scene.ply") && contains(m, "format")) << m;
}

TEST(LoadErrors, MalformedJson) {
  TempDir dir;
  const std::string path = dir.write("bad.illum.json", "{\"meshes\": [\n  {\"file\": \"x.obj\",\n");
  const std::string message = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "line")) << message;
  expect_one_line(message);
}

TEST(LoadErrors, UnknownJsonKey) {
  TempDir dir;
  dir.write("tri.obj", kTriangleObj);
  const std::string path = dir.write("s.illum.json", scene_json("[]", R"(, "lightz": 3)"));
  const std::string message = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "lightz")) << message;
  // Nested: a typo inside a light names the full key path.
  const std::string nested = dir.write(
      "n.illum.json",
      scene_json(R"([{"type": "point", "position": [0,1,0], "flux": 1, "colour": [1,1,1]}])"));
  const std::string m2 = error_of([&] { load_scene(nested); });
  EXPECT_TRUE(contains(m2, "lights[0].colour")) << m2;
  expect_one_line(m2);
}

TEST(LoadErrors, UnknownLightType) {
  TempDir dir;
  dir.write("tri.obj", kTriangleObj);
  const std::string path =
      dir.write("s.illum.json", scene_json(R"([{"type": "laser", "position": [0,1,0]}])"));
  const std::string message = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "laser")) << message;
  EXPECT_TRUE(contains(message, "lights[0].type")) << message;
}

TEST(LoadErrors, NegativeFluxAndBadCone) {
  TempDir dir;
  dir.write("tri.obj", kTriangleObj);
  const std::string neg = dir.write(
      "neg.illum.json", scene_json(R"([{"type": "point", "position": [0,1,0], "flux": -5}])"));
  const std::string m1 = error_of([&] { load_scene(neg); });
  EXPECT_TRUE(contains(m1, "flux") && contains(m1, "negative") && contains(m1, neg)) << m1;
  for (const char* angle : {"0", "-10", "90.5", "120"}) {
    const std::string p = dir.write(
        "cone.illum.json",
        scene_json(std::string(R"([{"type": "spot", "position": [0,1,0], "direction": [0,-1,0],
                   "flux": 10, "half_angle_deg": )") +
                   angle + "}]"));
    const std::string m = error_of([&] { load_scene(p); });
    EXPECT_TRUE(contains(m, "half_angle_deg")) << angle << ": " << m;
  }
  // 90° (a hemisphere) is the largest cone allowed.
  const std::string ok = dir.write(
      "ok.illum.json", scene_json(R"([{"type": "spot", "position": [0,1,0], "direction": [0,-1,0],
                   "flux": 10, "half_angle_deg": 90}])"));
  const Scene scene = load_scene(ok);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_NEAR(scene.lights[0].intensity.g, 10.0f / (2.0f * kPi), 1e-5f);
  // Both flux and intensity is ambiguous.
  const std::string both = dir.write(
      "both.illum.json",
      scene_json(R"([{"type": "point", "position": [0,1,0], "flux": 1, "intensity": 1}])"));
  EXPECT_TRUE(contains(error_of([&] { load_scene(both); }), "exactly one"));
}

TEST(LoadErrors, PointLightFluxToIntensity) {
  TempDir dir;
  dir.write("tri.obj", kTriangleObj);
  const std::string path = dir.write(
      "p.illum.json",
      scene_json(R"([{"type": "point", "position": [0,1,0], "flux": 100, "color": [1, 0.5, 0]},
                     {"type": "sun", "direction": [0, -2, 0], "irradiance": 3}])"));
  const Scene scene = load_scene(path);
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_NEAR(scene.lights[0].intensity.r, 100.0f / (4.0f * kPi), 1e-4f);
  EXPECT_NEAR(scene.lights[0].intensity.g, 50.0f / (4.0f * kPi), 1e-4f);
  EXPECT_EQ(scene.lights[1].type, LightType::kDirectional);
  EXPECT_EQ(scene.lights[1].direction, vec3(0.0f, -1.0f, 0.0f));
  EXPECT_EQ(scene.lights[1].irradiance, Color(3.0f));
}

TEST(LoadErrors, NonFiniteVertex) {
  TempDir dir;
  // 1e39 overflows float (tinyobjloader would turn it into inf): caught with its line.
  const std::string inf = dir.write("inf.obj", "o thing\nv 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string m1 = error_of([&] { load_scene(inf); });
  EXPECT_TRUE(contains(m1, inf)) << m1;
  EXPECT_TRUE(contains(m1, "line 3")) << m1;
  expect_one_line(m1);
  // A literal nan (which tinyobjloader would read as 0) is caught with its line.
  const std::string nan = dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  const std::string m2 = error_of([&] { load_scene(nan); });
  EXPECT_TRUE(contains(m2, nan) && contains(m2, "line 3")) << m2;
  const std::string vn =
      dir.write("vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 inf\nf 1//1 2//1 3//1\n");
  EXPECT_TRUE(contains(error_of([&] { load_scene(vn); }), "line 4"));
}

TEST(LoadErrors, OutOfRangeIndex) {
  TempDir dir;
  const std::string path = dir.write("idx.obj", "o bad\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  const std::string message = error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "vertex 9")) << message;
  expect_one_line(message);
  const std::string neg = dir.write("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n");
  EXPECT_TRUE(contains(error_of([&] { load_scene(neg); }), neg));
}

TEST(LoadErrors, DegenerateTrianglesDroppedAndCounted) {
  TempDir dir;
  const std::string path = dir.write("deg.obj",
                                     "o mix\n"
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                     "v 1 0 0\n"    // 4: same position as 2
                                     "v 2 0 0\n"    // 5: collinear with 1, 2
                                     "f 1 2 3\n"    // good
                                     "f 1 1 3\n"    // repeated index
                                     "f 2 4 3\n"    // identical positions
                                     "f 1 2 5\n");  // zero area
  const Scene scene = load_scene(path);
  EXPECT_EQ(scene.triangle_count(), 1u);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_TRUE(contains(scene.warnings[0], "dropped 3 degenerate")) << scene.warnings[0];
  EXPECT_TRUE(contains(scene.warnings[0], path)) << scene.warnings[0];
  // A thin but real triangle stays.
  const std::string thin = dir.write("thin.obj", "v 0 0 0\nv 1 0 0\nv 0.5 0.001 0\nf 1 2 3\n");
  const Scene s2 = load_scene(thin);
  EXPECT_EQ(s2.triangle_count(), 1u);
  EXPECT_TRUE(s2.warnings.empty());
}

TEST(LoadErrors, EmptySceneLoadsWithWarning) {
  TempDir dir;
  const std::string path = dir.write("empty.illum.json", R"({"name": "nothing"})");
  const Scene scene = load_scene(path);
  EXPECT_EQ(scene.name, "nothing");
  EXPECT_EQ(scene.triangle_count(), 0u);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_TRUE(contains(scene.warnings[0], "no triangles")) << scene.warnings[0];
}

// Missing and unreadable textures: obj_texture_errors_test.cpp.

TEST(LoadErrors, HideUnknownObjectAndOverrideUnknownMaterial) {
  TempDir dir;
  dir.write("tri.obj", kTriangleObj);
  const std::string hide =
      dir.write("h.illum.json", R"({"meshes": [{"file": "tri.obj", "hide": ["trii"]}]})");
  const std::string m1 = error_of([&] { load_scene(hide); });
  EXPECT_TRUE(contains(m1, "trii") && contains(m1, "hide") && contains(m1, hide)) << m1;
  const std::string mat =
      dir.write("m.illum.json",
                R"({"meshes": [{"file": "tri.obj"}], "materials": {"gold": {"type": "mirror"}}})");
  const std::string m2 = error_of([&] { load_scene(mat); });
  EXPECT_TRUE(contains(m2, "gold") && contains(m2, mat)) << m2;
  const std::string type = dir.write(
      "t.illum.json",
      R"({"meshes": [{"file": "tri.obj"}], "materials": {"default": {"type": "velvet"}}})");
  EXPECT_TRUE(contains(error_of([&] { load_scene(type); }), "velvet"));
  const std::string missing_mesh =
      dir.write("mm.illum.json", R"({"meshes": [{"file": "nothere.obj"}]})");
  const std::string m3 = error_of([&] { load_scene(missing_mesh); });
  EXPECT_TRUE(contains(m3, "nothere.obj") && contains(m3, "cannot open")) << m3;
}

TEST(LoadErrors, JsonSceneFeatures) {
  TempDir dir;
  dir.write("tri.obj",
            "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 4 5 6\n");
  const std::string path = dir.write("s.illum.json", R"({
    "name": "features",
    "meshes": [{"file": "tri.obj", "scale": 2, "hide": ["b"],
                "transform": {"translate": [10, 0, 0], "rotate_deg": [0, 90, 0]}}],
    "materials": {"default": {"type": "mirror", "specular": [0.9, 0.9, 0.9], "emission": [0, 0, 1]}},
    "environment": {"constant": [0.1, 0.2, 0.3], "scale": 2},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y_deg": 50},
    "settings": {"width": 64, "height": 32, "spp": 4, "max_bounces": 3, "ambient": [0.1, 0, 0.2]}
  })");
  const Scene scene = load_scene(path);
  EXPECT_EQ(scene.triangle_count(), 1u);
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].name, "a");
  // p' = T · Ry(90°) · 2p: (1,0,0) → (10, 0, −2); (0,1,0) → (10, 2, 0).
  const Bounds3 b = scene.bounds();
  EXPECT_NEAR(b.min.x, 10.0f, 1e-5f);
  EXPECT_NEAR(b.max.y, 2.0f, 1e-5f);
  EXPECT_NEAR(b.min.z, -2.0f, 1e-5f);
  EXPECT_EQ(scene.materials[0].type, MaterialType::kMirror);
  // Emissive after the override: an area light, plus the environment light.
  int area = 0, env = 0;
  for (const Light& l : scene.lights) {
    area += l.type == LightType::kArea;
    env += l.type == LightType::kEnvironment;
  }
  EXPECT_EQ(area, 1);
  EXPECT_EQ(env, 1);
  ASSERT_TRUE(scene.environment.has_value());
  EXPECT_EQ(scene.environment->constant, Color(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(scene.environment->scale, 2.0f);
  EXPECT_EQ(scene.settings.width, 64);
  EXPECT_EQ(scene.settings.max_bounces, 3);
  EXPECT_EQ(scene.settings.ambient, Color(0.1f, 0.0f, 0.2f));
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_NEAR(scene.camera->fov_y, radians(50.0f), 1e-6f);
}

TEST(LoadErrors, MalformedGltf) {
  TempDir dir;
  const std::string bad = dir.write("bad.gltf", "{\"asset\": {\"version\": \"2.0\"},,}");
  const std::string m1 = error_of([&] { load_scene(bad); });
  EXPECT_TRUE(contains(m1, bad)) << m1;
  expect_one_line(m1);
  const std::string no_asset = dir.write("noasset.gltf", R"({"meshes": []})");
  const std::string m2 = error_of([&] { load_scene(no_asset); });
  EXPECT_TRUE(contains(m2, no_asset) && contains(m2, "asset")) << m2;
  // A primitive without POSITION.
  const std::string no_pos = dir.write("nopos.gltf", R"({"asset": {"version": "2.0"},
    "meshes": [{"primitives": [{"attributes": {}}]}], "nodes": [{"mesh": 0}],
    "scenes": [{"nodes": [0]}]})");
  const std::string m3 = error_of([&] { load_scene(no_pos); });
  EXPECT_TRUE(contains(m3, no_pos)) << m3;
  expect_one_line(m3);
  const std::string glb = dir.write("bad.glb", "not a glb at all");
  const std::string m4 = error_of([&] { load_scene(glb); });
  EXPECT_TRUE(contains(m4, glb)) << m4;
  expect_one_line(m4);
}

TEST(LoadErrors, JsonNestingAndNumbersInSceneFiles) {
  TempDir dir;
  dir.write("tri.obj", kTriangleObj);
  // A million levels is refused before any parser (Params copies sub-objects recursively).
  const int levels = 1000000;
  const std::string deep =
      dir.write("deep.illum.json",
                "{\"description\": " + std::string(levels, '[') + std::string(levels, ']') + "}");
  const std::string m1 = error_of([&] { load_scene(deep); });
  EXPECT_TRUE(contains(m1, deep) && contains(m1, "JSON nested deeper than 128 levels")) << m1;
  expect_one_line(m1);
  // Brackets inside strings and comments are not nesting.
  const std::string fine =
      dir.write("fine.illum.json", "// " + std::string(300, '[') + "\n/* " + std::string(300, '{') +
                                       " */\n{\"description\": \"" + std::string(300, '[') +
                                       "\\\" [[\", \"meshes\": [{\"file\": \"tri.obj\"}]}");
  EXPECT_EQ(load_scene(fine).triangle_count(), 1u);
  // A number beyond a double used to escape as nlohmann's out_of_range (exit code 1).
  const std::string big =
      dir.write("big.illum.json",
                "{\"meshes\": [{\"file\": \"tri.obj\"}],\n"
                " \"lights\": [{\"type\": \"point\", \"position\": [0, 1, 0], \"flux\": 1e400}]}");
  const std::string m2 = error_of([&] { load_scene(big); });
  EXPECT_TRUE(contains(m2, big) && contains(m2, "number 1e400 is out of range (line 2, column 62)"))
      << m2;
  expect_one_line(m2);
}

// One set of value rules (scene/scene_validation.h) for MTL, glTF and scene files.
TEST(LoadErrors, SameValueRulesForEveryFormat) {
  TempDir dir;
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  struct Case {
    const char* mtl;
    const char* expect;
  };
  const Case cases[] = {
      {"newmtl wood\nKd -0.5 0.4 0.3\n", "material 0 'wood' albedo = (-0.5, 0.4, 0.3) is negative"},
      {"newmtl wood\nKd 1.5 0.4 0.3\n", "material 0 'wood' albedo = (1.5, 0.4, 0.3) exceeds 1"},
      {"newmtl wood\nKe -1 0 0\n", "material 0 'wood' emission = (-1, 0, 0) is negative"},
      {"newmtl wood\nillum 7\nNi 0.5\n", "material 0 'wood' ior = 0.5 is outside [1, 10]"},
      {"newmtl wood\nKd 0.5 0.5 0.5\nd 1.5\n", "material 0 'wood' opacity = 1.5 is outside [0, 1]"},
  };
  const char* names[] = {"m0", "m1", "m2", "m3", "m4"};
  static_assert(std::size(names) == std::size(cases));
  for (size_t i = 0; i < std::size(cases); ++i) {
    const Case& c = cases[i];
    SCOPED_TRACE(c.mtl);
    const std::string name = names[i];
    dir.write(name + ".mtl", c.mtl);
    const std::string obj =
        dir.write(name + ".obj", "mtllib " + name + ".mtl\nusemtl wood\n" + tri);
    const std::string m = error_of([&] { load_scene(obj); });
    EXPECT_TRUE(contains(m, obj) && contains(m, c.expect)) << m;
    expect_one_line(m);
  }
  // Through a scene file the message names the OBJ, where the value is.
  const std::string scene = dir.write("s.illum.json", R"({"meshes": [{"file": "m0.obj"}]})");
  const std::string m1 = error_of([&] { load_scene(scene); });
  EXPECT_TRUE(contains(m1, dir.file("m0.obj")) && contains(m1, "'wood' albedo")) << m1;
  // The scene file's own override meets the same bound, under its key.
  dir.write("tri.obj", kTriangleObj);
  const std::string bright = dir.write(
      "b.illum.json",
      R"({"meshes": [{"file": "tri.obj"}], "materials": {"default": {"albedo": [1.5, 0, 0]}}})");
  const std::string m2 = error_of([&] { load_scene(bright); });
  EXPECT_TRUE(contains(m2, bright) &&
              contains(m2, "'materials.default.albedo' = (1.5, 0, 0) exceeds 1"))
      << m2;
}

// A failing load prints nothing before its error (the CLI adds the one line); a successful one
// logs each warning once.
TEST(LoadErrors, WarningsReachTheLogOnlyWhenTheLoadSucceeds) {
  TempDir dir;
  test::Asset a = test::make_asset();  // its points primitive is skipped with a warning
  const std::string good = test::write_gltf(dir, a, "good.gltf");
  ::testing::internal::CaptureStderr();
  const Scene scene = load_scene(good);
  const std::string logged = ::testing::internal::GetCapturedStderr();
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_TRUE(contains(logged, scene.warnings[0])) << logged;
  EXPECT_EQ(logged.find("mode 0"), logged.rfind("mode 0")) << logged;  // once
  // The same warning, then a fatal error: a zero scale on a node read after the meshes.
  a.json["nodes"][1]["scale"] = {0, 1, 1};
  const std::string bad = test::write_gltf(dir, a, "bad.gltf");
  ::testing::internal::CaptureStderr();
  const std::string message = error_of([&] { load_scene(bad); });
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_TRUE(contains(message, "singular transform")) << message;
  // And through a scene file that merges it.
  const std::string wrapper = dir.write("w.illum.json", R"({"meshes": [{"file": "bad.gltf"}]})");
  ::testing::internal::CaptureStderr();
  error_of([&] { load_scene(wrapper); });
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace illum
