#include "illum/realtime/gpu_scene.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <unordered_map>

#include <meshoptimizer.h>

namespace illum::realtime {

// One cluster's triangles (`count` corners at `vertices`, the same welded at `positions`)
// reordered in place, the set kept, for the GPU's reuse of transformed vertices
// (meshoptimizer's vertex cache order of the welded corners; the full ones follow the same
// permutation). On the H200 a vertex shader invocation costs about as much as setting up a
// triangle, and the cluster split leaves triangles in no useful order: Sibenik 1080p, the
// cascades took 0.68 → 0.54 ms with this order on the full corners
// (bench/results/raster.md#design-choices; the run is in git at c416128). Ordering for overdraw on
// top (meshopt_optimizeOverdraw) was measured too and was 0.5–1.5 % slower. The cluster's vertices
// are numbered locally so the work follows the cluster, not the mesh.
static void order_within_cluster(uint32_t* vertices, uint32_t* positions, size_t count) {
  std::unordered_map<uint32_t, uint32_t> local_of;
  std::vector<uint32_t> global, local(count);
  for (size_t i = 0; i < count; ++i) {
    const auto [it, added] =
        local_of.try_emplace(positions[i], static_cast<uint32_t>(global.size()));
    if (added) global.push_back(positions[i]);
    local[i] = it->second;
  }
  std::vector<uint32_t> ordered(count);
  meshopt_optimizeVertexCache(ordered.data(), local.data(), count, global.size());
  // meshoptimizer moves whole triangles with their corners in order: each output triangle is
  // a source triangle with the same three local corners (duplicates taken in turn).
  auto key = [](const uint32_t* t) {
    return (uint64_t(t[0]) << 42) | (uint64_t(t[1]) << 21) | uint64_t(t[2]);
  };
  std::unordered_map<uint64_t, std::vector<uint32_t>> sources;
  for (size_t t = count / 3; t-- > 0;) sources[key(&local[3 * t])].push_back(uint32_t(t));
  const std::vector<uint32_t> full(vertices, vertices + count),
      welded(positions, positions + count);
  for (size_t t = 0; t < count / 3; ++t) {
    auto it = sources.find(key(&ordered[3 * t]));
    ILLUM_CHECK(it != sources.end() && !it->second.empty(),
                "the vertex cache order turned or lost a triangle");
    const uint32_t from = it->second.back();
    it->second.pop_back();
    for (int k = 0; k < 3; ++k) {
      vertices[3 * t + k] = full[3 * from + k];
      positions[3 * t + k] = welded[3 * from + k];
    }
  }
}

// The mesh's triangles reordered so that every run of `cluster` of them (the last run may be
// shorter) is spatially compact: centroids split recursively at the median of their longest
// axis, each split on a multiple of `cluster`. (Not a Morton order: its runs jump across cell
// boundaries, and Sibenik's clusters came out as wide as the nave.)
ClusteredIndices clustered_indices(const Mesh& mesh, uint32_t cluster) {
  const size_t triangles = mesh.indices.size() / 3;
  std::vector<vec3> centroid(triangles);
  for (size_t t = 0; t < triangles; ++t)
    centroid[t] = (mesh.positions[mesh.indices[3 * t]] + mesh.positions[mesh.indices[3 * t + 1]] +
                   mesh.positions[mesh.indices[3 * t + 2]]) /
                  3.0f;
  std::vector<uint32_t> order(triangles);
  for (size_t t = 0; t < triangles; ++t) order[t] = static_cast<uint32_t>(t);
  std::vector<std::pair<size_t, size_t>> todo{{0, triangles}};
  while (!todo.empty()) {
    const auto [begin, end] = todo.back();
    todo.pop_back();
    if (end - begin <= cluster) continue;
    Bounds3 b;
    for (size_t i = begin; i < end; ++i) b.extend(centroid[order[i]]);
    const vec3 e = b.extent();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
    const size_t half = (end - begin) / cluster / 2 * cluster;  // whole clusters on the left
    const size_t mid = begin + std::max<size_t>(half, cluster);
    // Ties broken by triangle number, so the order does not depend on the library's sort.
    std::nth_element(order.begin() + static_cast<ptrdiff_t>(begin),
                     order.begin() + static_cast<ptrdiff_t>(mid),
                     order.begin() + static_cast<ptrdiff_t>(end), [&](uint32_t x, uint32_t y) {
                       const float cx = centroid[x][axis], cy = centroid[y][axis];
                       return cx < cy || (cx == cy && x < y);
                     });
    todo.push_back({begin, mid});
    todo.push_back({mid, end});
  }
  std::vector<uint32_t> welded(mesh.indices.size());
  if (!welded.empty())
    meshopt_generateShadowIndexBuffer(welded.data(), mesh.indices.data(), mesh.indices.size(),
                                      mesh.positions.data(), mesh.positions.size(), sizeof(vec3),
                                      sizeof(vec3));
  ClusteredIndices out;
  out.vertices.reserve(3 * triangles);
  out.positions.reserve(3 * triangles);
  for (uint32_t t : order)
    for (int k = 0; k < 3; ++k) {
      out.vertices.push_back(mesh.indices[3 * t + k]);
      out.positions.push_back(welded[3 * t + k]);
    }
  for (size_t first = 0; first < out.vertices.size(); first += 3 * size_t(cluster))
    order_within_cluster(out.vertices.data() + first, out.positions.data() + first,
                         std::min(out.vertices.size() - first, 3 * size_t(cluster)));
  return out;
}

GpuScene::GpuScene(gpu::Context& context, const Scene& scene) : scene_(scene) {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices, position_indices;
  for (const Mesh& mesh : scene.meshes) {
    MeshRange range;
    range.first_index = static_cast<uint32_t>(indices.size());
    range.index_count = static_cast<uint32_t>(mesh.indices.size());
    range.vertex_offset = static_cast<int32_t>(vertices.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      Vertex v{};
      v.position = mesh.positions[i];
      v.normal = i < mesh.normals.size() ? mesh.normals[i] : vec3(0.0f);
      v.tangent = i < mesh.tangents.size() ? mesh.tangents[i] : vec4(0.0f);
      v.uv0 = i < mesh.uv0.size() ? mesh.uv0[i] : vec2(0.0f);
      v.uv1 = i < mesh.uv1.size() ? mesh.uv1[i] : vec2(0.0f);
      vertices.push_back(v);
    }
    const ClusteredIndices ordered = clustered_indices(mesh, kClusterTriangles);
    indices.insert(indices.end(), ordered.vertices.begin(), ordered.vertices.end());
    position_indices.insert(position_indices.end(), ordered.positions.begin(),
                            ordered.positions.end());
    meshes_.push_back(range);
  }
  // Meshes without normals get flat per-vertex normals from their first triangle use, so a
  // hand-built scene still shades (loaders fill normals; this is a guard).
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.normals.empty()) continue;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const vec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                 c = mesh.positions[mesh.indices[t + 2]];
      const vec3 n = glm::normalize(glm::cross(b - a, c - a));
      for (int k = 0; k < 3; ++k)
        vertices[static_cast<size_t>(meshes_[m].vertex_offset) + mesh.indices[t + k]].normal = n;
    }
  }
  for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
    const Instance& inst = scene.instances[ii];
    ILLUM_CHECK(inst.mesh >= 0 && static_cast<size_t>(inst.mesh) < scene.meshes.size(),
                "instance mesh out of range");
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    if (mesh.indices.empty()) continue;
    DrawItem item{static_cast<uint32_t>(inst.mesh), mesh.material, inst.transform};
    item.first_cluster = static_cast<uint32_t>(clusters_.size());
    const MeshRange& range = meshes_[static_cast<size_t>(inst.mesh)];
    const uint32_t mesh_triangles = range.index_count / 3;
    for (uint32_t t0 = 0; t0 < mesh_triangles; t0 += kClusterTriangles) {
      Cluster c;
      c.draw = static_cast<uint32_t>(draws_.size());
      c.first_triangle = t0;
      c.first_index = range.first_index + 3 * t0;
      c.index_count = 3 * std::min(kClusterTriangles, mesh_triangles - t0);
      for (uint32_t i = 0; i < c.index_count; ++i) {
        const uint32_t v = indices[c.first_index + i];
        c.bounds.extend(vec3(inst.transform * vec4(mesh.positions[v], 1.0f)));
      }
      bounds_.extend(c.bounds);
      clusters_.push_back(c);
    }
    item.cluster_count = static_cast<uint32_t>(clusters_.size()) - item.first_cluster;
    draws_.push_back(item);
    draw_instances_.push_back(static_cast<int>(ii));
    triangles_ += mesh.triangle_count();
  }
  if (vertices.empty()) vertices.push_back(Vertex{});
  if (indices.empty()) indices.push_back(0);
  if (position_indices.empty()) position_indices.push_back(0);
  const VkBufferUsageFlags vb =
      VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  vertices_ =
      gpu::make_device_buffer(context, vertices.data(), vertices.size() * sizeof(Vertex), vb);
  std::vector<vec3> positions(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) positions[i] = vertices[i].position;
  positions_ = gpu::make_device_buffer(context, positions.data(), positions.size() * sizeof(vec3),
                                       VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  indices_ = gpu::make_device_buffer(
      context, indices.data(), indices.size() * sizeof(uint32_t),
      VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  position_indices_ = gpu::make_device_buffer(context, position_indices.data(),
                                              position_indices.size() * sizeof(uint32_t),
                                              VK_BUFFER_USAGE_INDEX_BUFFER_BIT);

  std::vector<GpuMaterial> materials;
  for (const Material& m : scene.materials) {
    GpuMaterial g{};
    g.albedo = vec4(m.albedo, m.opacity);
    g.specular = vec4(m.specular, m.exponent);
    g.emission = vec4(m.emission, m.normal_scale);
    g.textures = glm::ivec4(m.albedo_texture, m.normal_texture, m.emission_texture, kNoTexture);
    g.info = glm::ivec4(static_cast<int>(m.type), 0, 0, 0);
    materials.push_back(g);
  }
  if (materials.empty())
    materials.push_back(GpuMaterial{vec4(0.8f, 0.8f, 0.8f, 1.0f), vec4(0.0f),
                                    vec4(0.0f, 0.0f, 0.0f, 1.0f), glm::ivec4(-1), glm::ivec4(0)});
  materials_ =
      gpu::make_device_buffer(context, materials.data(), materials.size() * sizeof(GpuMaterial),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);

  for (const Texture& t : scene.textures) {
    gpu::ImageDesc desc;
    desc.width = static_cast<uint32_t>(std::max(1, t.image.width()));
    desc.height = static_cast<uint32_t>(std::max(1, t.image.height()));
    desc.mips = static_cast<uint32_t>(std::bit_width(std::max(desc.width, desc.height)));
    desc.format = t.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    gpu::GpuImage image(context, desc);
    image.upload(t.image.empty() ? Image(1, 1, 4, 1.0f) : t.image);
    textures_.push_back(std::move(image));
  }
}

}  // namespace illum::realtime
