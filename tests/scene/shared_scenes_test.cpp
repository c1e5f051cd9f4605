// Loaders on the project's built-in scenes and the shared test scenes (../shared/scenes).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "illum/core/error.h"
#include "illum/scene/load.h"
#include "test_support/prerequisites.h"
#include "test_util.h"

namespace illum {
namespace {

using test::contains;

const Material* find_material(const Scene& scene, const std::string& name) {
  for (const Material& m : scene.materials)
    if (m.name == name) return &m;
  return nullptr;
}

int count_lights(const Scene& scene, LightType type) {
  int n = 0;
  for (const Light& l : scene.lights) n += l.type == type;
  return n;
}

void expect_unit_normals(const Scene& scene) {
  for (const Mesh& mesh : scene.meshes) {
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size()) << mesh.name;
    for (const vec3& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f) << mesh.name;
  }
}

TEST(SharedScenes, CornellBuiltin) {
  const Scene scene = load_scene("cornell");
  EXPECT_EQ(scene.name, "cornell");
  // 15 quads (2 triangles each) + the red wall's 2 triangles.
  EXPECT_EQ(scene.triangle_count(), 32u);
  EXPECT_EQ(scene.instances.size(), 8u);
  EXPECT_EQ(count_lights(scene, LightType::kArea), 1);
  EXPECT_EQ(scene.lights.size(), 1u);
  const Bounds3 b = scene.bounds();
  EXPECT_NEAR(b.min.x, 0.0f, 1e-6f);
  EXPECT_NEAR(b.min.y, 0.0f, 1e-6f);
  EXPECT_NEAR(b.min.z, 0.0f, 1e-6f);
  EXPECT_NEAR(b.max.x, 0.556f, 1e-5f);
  EXPECT_NEAR(b.max.y, 0.5488f, 1e-5f);
  EXPECT_NEAR(b.max.z, 0.5592f, 1e-5f);
  const Material* red = find_material(scene, "red");
  ASSERT_NE(red, nullptr);
  EXPECT_EQ(red->type, MaterialType::kLambert);
  EXPECT_NEAR(red->albedo.r, 0.63f, 1e-6f);
  EXPECT_NEAR(red->albedo.g, 0.065f, 1e-6f);
  EXPECT_NEAR(red->albedo.b, 0.05f, 1e-6f);
  const Material* light = find_material(scene, "light");
  ASSERT_NE(light, nullptr);
  EXPECT_EQ(light->emission, Color(17.0f, 12.0f, 4.0f));
  // The area light's instance is the emitter.
  const Light& area = scene.lights[0];
  EXPECT_EQ(scene.materials[scene.meshes[scene.instances[area.instance].mesh].material].name,
            "light");
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_NEAR(scene.camera->position.z, -0.8f, 1e-6f);
  EXPECT_NEAR(scene.camera->fov_y, radians(39.3077f), 1e-6f);
  EXPECT_EQ(scene.settings.width, 512);
  EXPECT_TRUE(scene.warnings.empty());
  expect_unit_normals(scene);
  // The floor's normal from the file is +y (vertices not shared, normals given).
  for (const Instance& inst : scene.instances) {
    if (inst.name != "floor") continue;
    for (const vec3& n : scene.meshes[inst.mesh].normals) EXPECT_NEAR(n.y, 1.0f, 1e-6f);
  }
}

TEST(SharedScenes, CausticsBuiltin) {
  const Scene scene = load_scene("caustics");
  EXPECT_EQ(scene.triangle_count(), 20482u);
  const Material* glass = find_material(scene, "glass");
  ASSERT_NE(glass, nullptr);
  EXPECT_EQ(glass->type, MaterialType::kDielectric);
  EXPECT_FLOAT_EQ(glass->ior, 1.5f);
  EXPECT_EQ(glass->transmittance, Color(1.0f));
  const Material* floor = find_material(scene, "floor_grey");
  ASSERT_NE(floor, nullptr);
  EXPECT_EQ(floor->type, MaterialType::kLambert);
  ASSERT_EQ(count_lights(scene, LightType::kSpot), 1);
  const Light& spot = scene.lights[0];
  EXPECT_EQ(spot.type, LightType::kSpot);
  // The file's 100 W over the cone's solid angle 2π(1 − cos 25°) (S004), to float rounding.
  const double intensity =
      100.0 / (2.0 * 3.14159265358979323846 * (1.0 - std::cos(radians(25.0f))));
  EXPECT_NEAR(spot.intensity.r, intensity, 1e-6 * intensity);
  EXPECT_NEAR(spot.intensity.b, intensity, 1e-6 * intensity);
  EXPECT_NEAR(spot.cone_half_angle, radians(25.0f), 1e-6f);
  EXPECT_EQ(spot.position, vec3(0.0f, 1.5f, 0.0f));
  EXPECT_EQ(spot.direction, vec3(0.0f, -1.0f, 0.0f));
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_NEAR(scene.camera->fov_y, radians(40.0f), 1e-6f);
  const Bounds3 b = scene.bounds();
  EXPECT_NEAR(b.max.y, 0.45f, 1e-4f);
  EXPECT_TRUE(scene.warnings.empty());
  expect_unit_normals(scene);
}

// Counts, independently of the loader, the triangles of sibenik.obj outside `hidden` and
// those among them that are degenerate by illum's rule (repeated vertex, identical
// positions, or area ≤ 1e-14 × the squared diagonal of the object's bounding box).
struct FaceScan {
  size_t triangles = 0;
  size_t degenerate = 0;
};
FaceScan scan_obj(const std::string& path, const std::string& hidden) {
  std::ifstream in(path);
  std::vector<glm::dvec3> v;
  struct Object {
    std::string name;
    std::vector<std::array<long, 3>> faces;
  };
  std::vector<Object> objects(1);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) {
      std::istringstream s(line.substr(2));
      float x, y, z;  // as floats, like the loader
      s >> x >> y >> z;
      v.emplace_back(x, y, z);
    } else if (line.rfind("o ", 0) == 0) {
      objects.push_back({fmt::format("{}", std::string_view(line).substr(2)), {}});
    } else if (line.rfind("f ", 0) == 0) {
      std::istringstream s(line.substr(2));
      std::array<long, 3> f{};
      std::string tok;
      for (int i = 0; i < 3 && s >> tok; ++i) f[i] = std::stol(tok.substr(0, tok.find('/'))) - 1;
      EXPECT_FALSE(s >> tok) << "the scan expects triangles only";
      objects.back().faces.push_back(f);
    }
  }
  FaceScan out;
  for (const Object& o : objects) {
    if (o.name == hidden || o.faces.empty()) continue;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& f : o.faces)
      for (long i : f) {
        lo = glm::min(lo, v[i]);
        hi = glm::max(hi, v[i]);
      }
    const double scale_sq = glm::dot(hi - lo, hi - lo);
    for (const auto& f : o.faces) {
      ++out.triangles;
      const glm::dvec3 a = v[f[0]], b = v[f[1]], c = v[f[2]];
      const bool same = f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || a == b || b == c || a == c;
      const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
      if (same || area <= 1e-14 * scale_sq) ++out.degenerate;
    }
  }
  return out;
}

TEST(SharedScenes, SibenikBuiltin) {
  ILLUM_REQUIRE_SHARED_SCENE("sibenik/sibenik.obj");
  const std::string obj = test::shared_scene("sibenik/sibenik.obj");
  const FaceScan all = scan_obj(obj, "");
  EXPECT_EQ(all.triangles, 80479u);  // the README's count
  const FaceScan expected = scan_obj(obj, "glas__glas");
  ASSERT_GT(expected.degenerate, 0u);

  const Scene scene = load_scene("sibenik");
  EXPECT_EQ(scene.triangle_count(), expected.triangles - expected.degenerate);
  for (const Instance& inst : scene.instances) EXPECT_NE(inst.name, "glas__glas");
  int degenerate_warnings = 0;
  for (const std::string& w : scene.warnings) {
    if (!contains(w, "degenerate")) continue;
    ++degenerate_warnings;
    EXPECT_TRUE(contains(w, fmt::format(" {} ", expected.degenerate))) << w;
    EXPECT_TRUE(contains(w, "sibenik.illum.json")) << w;
  }
  EXPECT_EQ(degenerate_warnings, 1);
  EXPECT_EQ(count_lights(scene, LightType::kSpot), 3);
  EXPECT_EQ(count_lights(scene, LightType::kDirectional), 1);
  ASSERT_TRUE(scene.camera.has_value());
  // The camera stands inside the cathedral's interior.
  const Bounds3 b = scene.bounds();
  EXPECT_GT(scene.camera->position.x, b.min.x);
  EXPECT_LT(scene.camera->position.x, b.max.x);
  // Three textures (stone, column stone, marble) are found and decoded.
  EXPECT_EQ(scene.textures.size(), 3u);
  expect_unit_normals(scene);
}

TEST(SharedScenes, Bunny) {
  ILLUM_REQUIRE_SHARED_SCENE("bunny/bunny.obj");
  const std::string path = test::shared_scene("bunny/bunny.obj");
  const Scene scene = load_scene(path);
  EXPECT_EQ(scene.name, "bunny");
  EXPECT_EQ(scene.triangle_count(), 69451u);
  EXPECT_TRUE(scene.warnings.empty());
  ASSERT_EQ(scene.meshes.size(), 1u);
  // The file has no normals: smooth ones are computed over the shared vertices, and they
  // point outward (the scan is CCW from outside): the top of the head faces up.
  expect_unit_normals(scene);
  const Mesh& mesh = scene.meshes[0];
  size_t top = 0;
  for (size_t i = 1; i < mesh.positions.size(); ++i)
    if (mesh.positions[i].y > mesh.positions[top].y) top = i;
  EXPECT_GT(mesh.normals[top].y, 0.5f);
  // The height range of the vertices the faces use, read from the file here (not from
  // numbers printed by an earlier run); the loader's floats may differ by their rounding.
  std::vector<double> ys;
  double lo = 1e30, hi = -1e30;
  std::ifstream obj(path);
  for (std::string line; std::getline(obj, line);) {
    std::istringstream in(line);
    std::string tag;
    in >> tag;
    if (tag == "v") {
      double x = 0, y = 0;
      in >> x >> y;
      ys.push_back(y);
    } else if (tag == "f") {
      for (std::string corner; in >> corner;) {
        const double y = ys.at(static_cast<size_t>(std::stol(corner) - 1));
        lo = std::min(lo, y);
        hi = std::max(hi, y);
      }
    }
  }
  const Bounds3 b = scene.bounds();
  EXPECT_NEAR(b.min.y, lo, 1e-6 * std::abs(lo));
  EXPECT_NEAR(b.max.y, hi, 1e-6 * std::abs(hi));
}

TEST(SharedScenes, SponzaMissingBufferIsAnError) {
  ILLUM_REQUIRE_SHARED_SCENE("sponza/glTF/Sponza.gltf");
  const std::string path = test::shared_scene("sponza/glTF/Sponza.gltf");
  const std::string message = test::error_of([&] { load_scene(path); });
  EXPECT_TRUE(contains(message, "missing buffer")) << message;
  EXPECT_TRUE(contains(message, "Sponza.gltf")) << message;
  EXPECT_TRUE(contains(message, "Sponza.bin")) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(SharedScenes, BuiltinNamesAndDataDir) {
  const auto names = builtin_scene_names();
  EXPECT_EQ(names.size(), 5u);
  for (const std::string& name : names) {
    const std::string path = fmt::format("{}/scenes/{}/{}.illum.json", data_dir(), name, name);
    EXPECT_TRUE(std::ifstream(path).good()) << path;
  }
  // $ILLUM_DATA_DIR overrides the compiled-in folder.
  ::setenv("ILLUM_DATA_DIR", "/nonexistent-illum-data", 1);
  EXPECT_EQ(data_dir(), "/nonexistent-illum-data");
  const std::string message = test::error_of([] { load_scene("cornell"); });
  EXPECT_TRUE(contains(message, "/nonexistent-illum-data")) << message;
  ::unsetenv("ILLUM_DATA_DIR");
  EXPECT_EQ(data_dir(), std::string(ILLUM_DATA_DIR));
}

}  // namespace
}  // namespace illum
