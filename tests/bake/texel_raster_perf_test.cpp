// Timing of the texel raster on Sibenik (75k triangles) at 2048² (label slow). The uv1
// layout is synthetic and harsh: every triangle gets its own 7-texel cell (no atlas builder
// involved), so most covered texels are chart-border texels that need overlap areas.
// Checks that every triangle's centroid texel is covered by that triangle or a neighbour
// sharing the texel, and prints the time.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "illum/atlas/texel_raster.h"
#include "illum/core/parallel.h"
#include "illum/scene/load.h"
#include "test_support/prerequisites.h"

namespace illum {
namespace {

TEST(TexelRasterPerf, Sibenik2048) {
  ILLUM_REQUIRE_SHARED_SCENE("sibenik/sibenik.obj");  // the built-in sibenik reads it
  Scene scene = load_scene("sibenik");
  const int size = 2048;
  const size_t triangles = scene.triangle_count();
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(triangles))));
  const float cell = 1.0f / static_cast<float>(cols);
  std::vector<vec2> centroids;
  size_t t = 0;
  // Unshare vertices so each triangle can have its own uv1 (as an atlas splits seams).
  for (Mesh& mesh : scene.meshes) {
    Mesh split;
    split.name = mesh.name;
    split.material = mesh.material;
    for (size_t f = 0; f < mesh.triangle_count(); ++f, ++t) {
      const vec2 origin(static_cast<float>(t % cols) * cell, static_cast<float>(t / cols) * cell);
      const vec2 corners[3] = {origin + vec2(0.1f, 0.1f) * cell, origin + vec2(0.9f, 0.1f) * cell,
                               origin + vec2(0.1f, 0.9f) * cell};
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.indices[3 * f + k];
        split.positions.push_back(mesh.positions[v]);
        split.normals.push_back(mesh.normals[v]);
        if (!mesh.tangents.empty()) split.tangents.push_back(mesh.tangents[v]);
        split.uv1.push_back(corners[k]);
        split.indices.push_back(static_cast<uint32_t>(split.indices.size()));
      }
      centroids.push_back((corners[0] + corners[1] + corners[2]) / 3.0f);
    }
    mesh = std::move(split);
  }
  const auto start = std::chrono::steady_clock::now();
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, size, size);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("sibenik %zu triangles at %d²: %zu texels covered in %.3f s (%d threads)\n",
              triangles, size, raster.covered(), seconds, ThreadLimit::hardware_threads());
  RecordProperty("seconds", std::to_string(seconds));
  for (const vec2& c : centroids) {
    const int x = static_cast<int>(c.x * size), y = static_cast<int>(c.y * size);
    ASSERT_GE(raster.at(x, y), 0) << x << "," << y;
  }
  for (const atlas::TexelSample& s : raster.samples)
    ASSERT_NEAR(glm::length(s.normal), 1.0f, 1e-4f);
}

}  // namespace
}  // namespace illum
