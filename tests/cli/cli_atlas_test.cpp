// `illum bake` and the atlas a scene asks for: a mesh's own light-map UVs (glTF TEXCOORD_1)
// kept, refused with a warning, or charted anew with --regenerate-uv1; a scene file's
// per-mesh `"lightmap": {"texel_size": s}` over --texel-size, and its bad values refused
// with one line, exit 2 and no folder.
#include <array>
#include <cmath>
#include <cstring>
#include <utility>

#include "cli_fixture.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;
using illum_cli_test::slurp;

struct ChartRect {
  uint32_t mesh, x, y, width, height;
};

// The charts of a light-map folder's atlas.bin (src/illum/atlas/README.md, "File format").
std::vector<ChartRect> charts_of(const fs::path& atlas_bin, float* texel_size) {
  const std::string bytes = slurp(atlas_bin);
  std::vector<ChartRect> charts;
  if (bytes.size() < 32 || bytes.compare(0, 8, "ILLUMATL") != 0) return charts;
  uint32_t count = 0;
  std::memcpy(texel_size, bytes.data() + 20, 4);
  std::memcpy(&count, bytes.data() + 24, 4);
  if (bytes.size() < 32 + size_t(count) * sizeof(ChartRect)) return charts;
  charts.resize(count);
  std::memcpy(charts.data(), bytes.data() + 32, size_t(count) * sizeof(ChartRect));
  return charts;
}

class AtlasCli : public CliTest {
 protected:
  Result bake(const std::string& scene, const std::string& extra = "") {
    return run("bake " + scene + " --resolution 64 --spp 1 --seed 1 " + extra + " -o " +
               (dir_ / "lm").string());
  }
  // Two 1 m quads side by side from quad.gltf, the second's entry with `lightmap` (JSON,
  // empty: none).
  std::string two_quads(const std::string& lightmap) {
    const std::string quad = quad_gltf("quad", {R"({"mesh": 0})"});
    return write("two.illum.json", R"({"meshes": [{"file": ")" + quad + R"("},
                    {"file": ")" + quad +
                                       R"(", "transform": {"translate": [3, 0, 0]})" +
                                       (lightmap.empty() ? "" : R"(, "lightmap": )" + lightmap) +
                                       "}]}")
        .string();
  }
  // A unit quad whose TEXCOORD_1 is `uv1` (4 pairs).
  std::string quad_with_uv1(const std::string& name, const std::array<float, 8>& uv1) {
    const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
    std::string bin(reinterpret_cast<const char*>(positions), sizeof(positions));
    bin.append(reinterpret_cast<const char*>(indices), sizeof(indices));
    bin.append(reinterpret_cast<const char*>(uv1.data()), sizeof(float) * 8);
    write(name + ".bin", bin);
    return write(name + ".gltf", R"({"asset": {"version": "2.0"}, "scene": 0,
"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_1": 2}, "indices": 1}]}],
"buffers": [{"uri": ")" + name + R"(.bin", "byteLength": 92}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                {"buffer": 0, "byteOffset": 48, "byteLength": 12},
                {"buffer": 0, "byteOffset": 60, "byteLength": 32}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
               "min": [0, 0, 0], "max": [1, 1, 0]},
              {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
              {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}]})")
        .string();
  }
};

// Cells of a 1 m chart at texel size s: ⌈1/s + 2/256⌉ (README.md "Cells").
int cells(double s) {
  return int(std::ceil(1.0 / s + 2.0 / 256.0));
}

TEST_F(AtlasCli, MeshTexelSizeOverridesTexelSize) {
  const Result r = bake(two_quads(R"({"texel_size": 0.05})"), "--texel-size 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  float texel_size = 0.0f;
  const std::vector<ChartRect> charts = charts_of(dir_ / "lm" / "atlas.bin", &texel_size);
  ASSERT_EQ(charts.size(), 2u);
  EXPECT_EQ(texel_size, 0.1f);
  for (const ChartRect& c : charts) {
    const int expected = c.mesh == 1 ? cells(0.05) : cells(0.1);  // 21 and 11
    EXPECT_EQ(int(c.width), expected) << "mesh " << c.mesh;
    EXPECT_EQ(int(c.height), expected) << "mesh " << c.mesh;
  }
}

TEST_F(AtlasCli, BadMeshTexelSizesAreOneLine) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"texel_size": 0})", "lightmap.texel_size"},
      {R"({"texel_size": -0.1})", "lightmap.texel_size"},
      {R"({"texel_size": 5000})", "lightmap.texel_size"},
      {R"({"texel_size": "fine"})", "lightmap.texel_size"},
      {R"({"texel_size": 1e999})", "two.illum.json"},
      {R"({})", "texel_size"},
      {R"({"texel_size": 0.1, "size": 2})", "lightmap.size"},
      {R"(0.1)", "must be an object"},
  };
  for (const auto& [lightmap, needle] : cases) {
    SCOPED_TRACE(lightmap);
    expect_bad_input(bake(two_quads(lightmap)), needle);
    EXPECT_FALSE(fs::exists(dir_ / "lm"));
  }
}

TEST_F(AtlasCli, KeepsAValidUv1UnlessAskedToRegenerate) {
  const std::string scene = quad_with_uv1("given", {0, 0, 1, 0, 1, 1, 0, 1});
  const Result kept = bake(scene);
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_NE(kept.err.find("kept the UV1 of 1 mesh"), std::string::npos) << kept.err;
  const Result regenerated = bake(scene, "--regenerate-uv1");
  ASSERT_EQ(regenerated.exit_code, 0) << regenerated.err;
  EXPECT_EQ(regenerated.err.find("kept the UV1"), std::string::npos) << regenerated.err;
  expect_bad_input(bake(scene, "--regenerate-uv1 -p reuse_uv1=true"), "--regenerate-uv1");
}

// An invalid UV1 is a warning (one line naming the mesh and the problem), not an error.
TEST_F(AtlasCli, ChartsAnInvalidUv1AnewWithOneWarning) {
  const Result r = bake(quad_with_uv1("tiled", {0, 0, 2, 0, 2, 2, 0, 2}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("cannot be its light-map layout"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("outside [0,1]"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("kept the UV1"), std::string::npos) << r.err;
  size_t warnings = 0;
  for (size_t at = r.err.find("light-map layout"); at != std::string::npos;
       at = r.err.find("light-map layout", at + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "lm" / "atlas.bin"));
}

}  // namespace
