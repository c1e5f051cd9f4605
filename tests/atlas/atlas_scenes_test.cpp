// Atlases of real scenes: the Cornell box and the Sibenik cathedral (75k triangles). Every
// promise of atlas.h is checked by check_atlas; the numbers (charts, texel size, occupancy,
// build time) are printed. Set ILLUM_ATLAS_PNG_DIR to get a picture of each atlas.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "atlas_check.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/core/error.h"
#include "illum/scene/load.h"
#include "test_support/prerequisites.h"

namespace illum::atlas {
namespace {

struct Built {
  Atlas atlas;
  double seconds = 0.0;
};

Built timed_build(const Scene& scene, const AtlasOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Built b;
  b.atlas = build_atlas(scene, options);
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return b;
}

void print(const std::string& name, const Built& b, const test::AtlasReport& r) {
  std::printf(
      "[ atlas    ] %s %d²: %d charts, texel %.5g m, occupancy %.1f%%, density ratio "
      "[%.4f, %.4f], %zu triangles (%zu degenerate, %zu slivers), build %.3f s\n",
      name.c_str(), b.atlas.width, b.atlas.chart_count, double(b.atlas.texel_size),
      100.0 * r.occupancy, r.min_density_ratio, r.max_density_ratio, r.triangles, r.degenerate,
      r.slivers, b.seconds);
}

Scene cornell() {
  Scene scene = load_scene("cornell");
  make_meshes_unique(scene);
  return scene;
}

TEST(AtlasScenes, Cornell) {
  const Scene scene = cornell();
  AtlasOptions options;
  options.resolution = 256;
  const Built b = timed_build(scene, options);
  const test::AtlasReport r = test::check_atlas(scene, b.atlas, options);
  print("cornell", b, r);
  test::maybe_write_picture("cornell_256", b.atlas, r);
  // Every chart of the box is planar: the density is exact, up to uv1 rounding.
  EXPECT_NEAR(r.min_density_ratio, 1.0, 1e-3);
  EXPECT_NEAR(r.max_density_ratio, 1.0, 1e-3);
  // The box's 17 planar faces (walls, light, two blocks' sides) are all the charts needed.
  EXPECT_LE(b.atlas.chart_count, 32);
  EXPECT_GT(r.occupancy, 0.3);

  // The same texel size given explicitly gives the same atlas.
  AtlasOptions fixed = options;
  fixed.texel_size = b.atlas.texel_size;
  const Atlas again = build_atlas(scene, fixed);
  for (size_t m = 0; m < again.meshes.size(); ++m)
    EXPECT_EQ(again.meshes[m].uv1, b.atlas.meshes[m].uv1);
  // 10% finer does not fit, and says so.
  fixed.texel_size = b.atlas.texel_size * 0.9f;
  EXPECT_THROW(build_atlas(scene, fixed), Error);
}

TEST(AtlasScenes, ApplyAtlasKeepsGeometry) {
  const Scene before = cornell();
  AtlasOptions options;
  options.resolution = 256;
  const Atlas atlas = build_atlas(before, options);
  Scene after = before;
  apply_atlas(after, atlas);
  ASSERT_EQ(after.meshes.size(), before.meshes.size());
  size_t split = 0;
  for (size_t m = 0; m < before.meshes.size(); ++m) {
    const Mesh &old_mesh = before.meshes[m], &mesh = after.meshes[m];
    const MeshLayout& layout = atlas.meshes[m];
    ASSERT_EQ(mesh.triangle_count(), old_mesh.triangle_count());
    ASSERT_EQ(mesh.uv1.size(), mesh.positions.size());
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    EXPECT_EQ(mesh.tangents.size(), old_mesh.tangents.empty() ? 0u : mesh.positions.size());
    EXPECT_EQ(mesh.uv0.size(), old_mesh.uv0.empty() ? 0u : mesh.positions.size());
    EXPECT_EQ(mesh.material, old_mesh.material);
    EXPECT_EQ(mesh.name, old_mesh.name);
    split += mesh.positions.size() - old_mesh.positions.size();
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
      const uint32_t v = mesh.indices[i], o = old_mesh.indices[i];
      // Same corner, same attributes: triangle t is still triangle t, same winding.
      EXPECT_EQ(mesh.positions[v], old_mesh.positions[o]);
      EXPECT_EQ(mesh.normals[v], old_mesh.normals[o]);
      if (!old_mesh.uv0.empty()) {
        EXPECT_EQ(mesh.uv0[v], old_mesh.uv0[o]);
      }
      if (!old_mesh.tangents.empty()) {
        EXPECT_EQ(mesh.tangents[v], old_mesh.tangents[o]);
      }
      EXPECT_EQ(mesh.uv1[v], layout.uv1[layout.indices[i]]);
    }
  }
  std::printf("[ atlas    ] cornell: %zu vertices added at chart seams\n", split);
  // The applied scene still satisfies every atlas promise (uv1 from the mesh itself).
  Atlas identity = atlas;
  for (size_t m = 0; m < after.meshes.size(); ++m) {
    MeshLayout& l = identity.meshes[m];
    l.source_vertex.resize(after.meshes[m].positions.size());
    for (uint32_t v = 0; v < l.source_vertex.size(); ++v) l.source_vertex[v] = v;
    l.uv1 = after.meshes[m].uv1;
    l.indices = after.meshes[m].indices;
    l.source_vertex_count = uint32_t(after.meshes[m].positions.size());
  }
  test::check_atlas(after, identity, options);
}

TEST(AtlasScenes, ApplyAtlasRefusesAnotherScene) {
  const Scene base = cornell();
  AtlasOptions options;
  options.resolution = 256;
  const Atlas atlas = build_atlas(base, options);
  auto refused = [&](Scene scene, const std::string& expected) {
    const Scene copy = scene;
    std::string message;
    try {
      apply_atlas(scene, atlas);
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(expected), std::string::npos) << "'" << message << "'";
    // Nothing changed.
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      EXPECT_EQ(scene.meshes[m].positions, copy.meshes[m].positions);
      EXPECT_TRUE(scene.meshes[m].uv1.empty());
    }
  };
  Scene fewer = base;
  fewer.meshes.pop_back();
  refused(fewer, "meshes");
  Scene more_vertices = base;
  more_vertices.meshes[3].positions.push_back(vec3(0.0f));
  more_vertices.meshes[3].normals.push_back(vec3(0.0f, 1.0f, 0.0f));
  refused(more_vertices, fmt::format("'{}'", base.meshes[3].name));
  Scene rewired = base;
  std::swap(rewired.meshes[2].indices[0], rewired.meshes[2].indices[1]);
  refused(rewired, fmt::format("'{}'", base.meshes[2].name));
  Scene fewer_triangles = base;
  fewer_triangles.meshes[1].indices.resize(fewer_triangles.meshes[1].indices.size() - 3);
  refused(fewer_triangles, "triangles");
}

// The texel raster (a separate implementation of coverage) agrees with the atlas: every
// texel it covers lies in the rectangle of its triangle's chart, and texels of different
// charts have at least `padding` empty texels between them.
void expect_raster_agrees(const Scene& scene, const Atlas& atlas, const AtlasOptions& options) {
  Scene applied = scene;
  apply_atlas(applied, atlas);
  const TexelRaster raster = rasterize_texels(applied, atlas.width, atlas.height);
  ASSERT_GT(raster.covered(), 0u);
  std::vector<int32_t> chart_at(size_t(atlas.width) * atlas.height, -1);
  size_t outside = 0, close = 0;
  for (const TexelSample& sample : raster.samples) {
    const int mesh = scene.instances[sample.instance].mesh;
    const uint32_t c = atlas.meshes[mesh].triangle_chart[sample.triangle];
    ASSERT_LT(c, atlas.charts.size());
    const AtlasChart& r = atlas.charts[c];
    outside +=
        sample.x < r.x || sample.x >= r.x + r.width || sample.y < r.y || sample.y >= r.y + r.height;
    chart_at[size_t(sample.y) * atlas.width + sample.x] = int32_t(c);
  }
  const int pad = options.padding;
  for (const TexelSample& sample : raster.samples) {
    const int32_t c = chart_at[size_t(sample.y) * atlas.width + sample.x];
    for (int y = std::max(0, sample.y - pad); y <= std::min(atlas.height - 1, sample.y + pad); ++y)
      for (int x = std::max(0, sample.x - pad); x <= std::min(atlas.width - 1, sample.x + pad);
           ++x) {
        const int32_t other = chart_at[size_t(y) * atlas.width + x];
        close += other >= 0 && other != c;
      }
  }
  EXPECT_EQ(outside, 0u) << "covered texels outside their chart's rectangle";
  EXPECT_EQ(close, 0u) << "covered texels of different charts closer than the padding";
}

TEST(AtlasScenes, TexelRasterAgreesOnCornell) {
  const Scene scene = cornell();
  AtlasOptions options;
  options.resolution = 256;
  expect_raster_agrees(scene, build_atlas(scene, options), options);
}

// Sibenik: 75k triangles of columns, arches and stairs.
class Sibenik : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!std::ifstream(::illum::test::shared_scene("sibenik/sibenik.obj")))
      return;  // SetUp reports it
    LoadOptions load;
    load.load_textures = false;
    scene_ = new Scene(load_scene("sibenik", load));
    make_meshes_unique(*scene_);
  }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  void SetUp() override { ILLUM_REQUIRE_SHARED_SCENE("sibenik/sibenik.obj"); }
  void run(int resolution) {
    AtlasOptions options;
    options.resolution = resolution;
    const Built b = timed_build(*scene_, options);
    const test::AtlasReport r = test::check_atlas(*scene_, b.atlas, options);
    print("sibenik", b, r);
    test::maybe_write_picture(fmt::format("sibenik_{}", resolution), b.atlas, r);
    EXPECT_EQ(r.triangles, scene_->triangle_count());
    // Charts: far fewer than triangles (region growing works), and a packing that is not
    // mostly empty (an occupancy bound that a shelf of single triangles would miss).
    EXPECT_LT(b.atlas.chart_count, int(scene_->triangle_count() / 4));
    EXPECT_GT(r.occupancy, 0.3);
    last_ = b.atlas;
  }
  static Scene* scene_;
  Atlas last_;
};
Scene* Sibenik::scene_ = nullptr;

TEST_F(Sibenik, Atlas1024) {
  run(1024);
  AtlasOptions options;
  options.resolution = 1024;
  expect_raster_agrees(*scene_, last_, options);
}

TEST_F(Sibenik, Atlas2048AndFileRoundTrip) {
  run(2048);
  const auto path = std::filesystem::temp_directory_path() /
                    fmt::format("illum_atlas_sibenik_{}.atlas", ::getpid());
  save_atlas(last_, path);
  const Atlas loaded = load_atlas(path);
  std::filesystem::remove(path);
  ASSERT_EQ(loaded.meshes.size(), last_.meshes.size());
  for (size_t m = 0; m < loaded.meshes.size(); ++m) {
    EXPECT_EQ(loaded.meshes[m].uv1, last_.meshes[m].uv1);
    EXPECT_EQ(loaded.meshes[m].indices, last_.meshes[m].indices);
    EXPECT_EQ(loaded.meshes[m].source_vertex, last_.meshes[m].source_vertex);
  }
  Scene applied = *scene_;
  apply_atlas(applied, loaded);
  EXPECT_EQ(applied.triangle_count(), scene_->triangle_count());
}

}  // namespace
}  // namespace illum::atlas
