#include "illum/realtime/gpu_scene.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace illum::realtime {

GpuScene::GpuScene(gpu::Context& context, const Scene& scene) : scene_(scene) {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
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
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
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
    draws_.push_back({static_cast<uint32_t>(inst.mesh), mesh.material, inst.transform});
    draw_instances_.push_back(static_cast<int>(ii));
    triangles_ += mesh.triangle_count();
    for (const vec3& p : mesh.positions) bounds_.extend(vec3(inst.transform * vec4(p, 1.0f)));
  }
  if (vertices.empty()) vertices.push_back(Vertex{});
  if (indices.empty()) indices.push_back(0);
  const VkBufferUsageFlags vb =
      VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  vertices_ =
      gpu::make_device_buffer(context, vertices.data(), vertices.size() * sizeof(Vertex), vb);
  indices_ = gpu::make_device_buffer(
      context, indices.data(), indices.size() * sizeof(uint32_t),
      VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);

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
