// The scene model on the GPU: one vertex and one index buffer for all meshes (draws use
// firstIndex/vertexOffset), materials and lights as storage buffers, textures as a bindless
// array (sRGB colour textures as R8G8B8A8_SRGB with mips).
#pragma once

#include <vector>

#include "illum/gpu/buffer.h"
#include "illum/gpu/gpu_image.h"
#include "illum/realtime/gpu_types.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

struct MeshRange {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
  int32_t vertex_offset = 0;
};

struct DrawItem {
  uint32_t mesh = 0;
  int material = 0;
  glm::mat4 transform{1.0f};
  uint32_t first_cluster = 0, cluster_count = 0;  // its clusters in GpuScene::clusters()
};

// Triangles per cluster: small enough that ordering clusters puts occluders first (H200,
// Sibenik 1080p, visibility frame: 2.033 ms at 512, 2.000 at 256, 1.994 at 128 — each
// draw costs ≈ 0.15 µs, so 256 keeps the draw count down; bench/results/raster.md#design-choices).
inline constexpr uint32_t kClusterTriangles = 256;

// The mesh's index list reordered for clustering: each run of `cluster` triangles (the last
// may be shorter) is a spatially compact piece of the surface; every triangle kept with its
// winding. Beside it the same triangles in the same order on welded positions: each index
// replaced by the first vertex with a bit-identical position — what depth-like passes, which
// read positions only, draw, so a corner split for its normal or texture coordinates is
// transformed once (meshopt_generateShadowIndexBuffer). The order within a cluster is for the
// GPU's reuse of the welded vertices (those passes outnumber the shading passes: every shadow
// view, the pre-pass, the visibility raster).
struct ClusteredIndices {
  std::vector<uint32_t> vertices;   // into the mesh's vertices
  std::vector<uint32_t> positions;  // the same corners, welded
};
ClusteredIndices clustered_indices(const Mesh& mesh, uint32_t cluster);

// A spatially compact run of one draw's triangles (the mesh's triangles are stored as
// clustered_indices orders them, so a run of the index buffer is a compact piece of the surface):
// the unit each view culls against its frustum and sorts front to back. `first_triangle`
// counts from the mesh's first index (the visibility buffer's triangle ids).
struct Cluster {
  uint32_t draw = 0;
  uint32_t first_index = 0, index_count = 0;
  uint32_t first_triangle = 0;
  Bounds3 bounds;  // world space
};

class GpuScene {
 public:
  GpuScene(gpu::Context& context, const Scene& scene);

  const Scene& scene() const { return scene_; }
  const gpu::Buffer& vertices() const { return vertices_; }
  // The vertices' positions alone, packed (12 bytes a vertex, the same order): the stream of
  // depth-like passes, which would otherwise fetch 56-byte vertices for 12 bytes of each.
  const gpu::Buffer& positions() const { return positions_; }
  const gpu::Buffer& indices() const { return indices_; }
  // The same triangles on welded positions (ClusteredIndices::positions), with the same
  // offsets: the index buffer of depth-like passes, which bind positions() as their stream.
  const gpu::Buffer& position_indices() const { return position_indices_; }
  const gpu::Buffer& materials() const { return materials_; }
  const std::vector<MeshRange>& meshes() const { return meshes_; }
  const std::vector<DrawItem>& draws() const { return draws_; }
  const std::vector<Cluster>& clusters() const { return clusters_; }
  const std::vector<int>& draw_instances() const { return draw_instances_; }  // per draw
  const std::vector<gpu::GpuImage>& textures() const { return textures_; }
  Bounds3 bounds() const { return bounds_; }
  size_t triangle_count() const { return triangles_; }

 private:
  const Scene& scene_;
  gpu::Buffer vertices_, positions_, indices_, position_indices_, materials_;
  std::vector<MeshRange> meshes_;
  std::vector<DrawItem> draws_;
  std::vector<Cluster> clusters_;
  std::vector<int> draw_instances_;
  std::vector<gpu::GpuImage> textures_;
  Bounds3 bounds_;
  size_t triangles_ = 0;
};

}  // namespace illum::realtime
