#include "illum/bake/prt_normal_map.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "illum/core/sampler.h"
#include "illum/scene/normal_map.h"

namespace illum::bake {

namespace {

const Material* material_of(const Scene& scene, const Mesh& mesh) {
  return mesh.material >= 0 && size_t(mesh.material) < scene.materials.size()
             ? &scene.materials[size_t(mesh.material)]
             : nullptr;
}

// The map and frame a point reads its normals with, or nullptr when it has none.
const Image* point_map(const Scene& scene, const Mesh& mesh, const Material** material) {
  *material = material_of(scene, mesh);
  if (!*material || mesh.uv0.size() != mesh.positions.size() ||
      mesh.tangents.size() != mesh.positions.size())
    return nullptr;
  return normal_map_of(scene, **material);
}

// Perturbed normals at the uv0 points, in the frame (t, b, n); points whose mapped vector
// has no length keep n.
void read_normals(const Image& map, const Material& material, std::span<const vec2> uv0,
                  const vec3& t, const vec3& b, const vec3& n, std::vector<vec3>& out) {
  out.resize(uv0.size());
  for (size_t k = 0; k < uv0.size(); ++k) {
    out[k] = n;
    mapped_normal(map, material.normal_scale, uv0[k], t, b, n, &out[k]);
  }
}

}  // namespace

VertexRing vertex_ring(const Mesh& mesh) {
  VertexRing ring;
  ring.first.assign(mesh.vertex_count() + 1, 0);
  for (uint32_t v : mesh.indices) ++ring.first[size_t(v) + 1];
  for (size_t v = 0; v < mesh.vertex_count(); ++v) ring.first[v + 1] += ring.first[v];
  ring.triangles.resize(mesh.indices.size());
  std::vector<uint32_t> next(ring.first.begin(), ring.first.end() - 1);
  for (size_t t = 0; t < mesh.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c)
      ring.triangles[next[mesh.indices[t * 3 + size_t(c)]]++] = uint32_t(t);
  return ring;
}

void texel_normal_samples(const Scene& scene, const atlas::TexelRaster& raster,
                          const atlas::TexelSample& sample, int count, uint64_t seed,
                          std::vector<vec3>& out) {
  out.clear();
  const Mesh& mesh = scene.meshes[size_t(scene.instances[size_t(sample.instance)].mesh)];
  const Material* material = nullptr;
  const Image* map = point_map(scene, mesh, &material);
  if (!map || mesh.uv1.size() != mesh.positions.size()) return;
  const uint32_t* idx = &mesh.indices[size_t(sample.triangle) * 3];
  // uv1 (texel units) → barycentric → uv0, affine on the sample's triangle.
  const glm::dvec2 size(raster.width, raster.height);
  const glm::dvec2 q0 = glm::dvec2(mesh.uv1[idx[0]]) * size;
  const glm::dvec2 e1 = glm::dvec2(mesh.uv1[idx[1]]) * size - q0;
  const glm::dvec2 e2 = glm::dvec2(mesh.uv1[idx[2]]) * size - q0;
  const double det = e1.x * e2.y - e1.y * e2.x;
  std::vector<vec2> uv0(static_cast<size_t>(count));
  const vec2 a0 = mesh.uv0[idx[0]], a1 = mesh.uv0[idx[1]], a2 = mesh.uv0[idx[2]];
  if (!(std::abs(det) > 1e-18)) {  // no area in uv1: the sample point's uv0 only
    const vec2 b = sample.barycentric;
    std::fill(uv0.begin(), uv0.end(), (1.0f - b.x - b.y) * a0 + b.x * a1 + b.y * a2);
  } else {
    SobolSampler sampler(seed);
    for (int k = 0; k < count; ++k) {
      sampler.start_sample(uint32_t(k));
      const glm::dvec2 p = glm::dvec2(sample.x, sample.y) + glm::dvec2(sampler.next_2d()) - q0;
      const double b1 = (p.x * e2.y - p.y * e2.x) / det, b2 = (e1.x * p.y - e1.y * p.x) / det;
      uv0[size_t(k)] = float(1.0 - b1 - b2) * a0 + float(b1) * a1 + float(b2) * a2;
    }
  }
  const vec3 b = glm::cross(sample.normal, sample.tangent) * sample.tangent_sign;
  read_normals(*map, *material, uv0, sample.tangent, b, sample.normal, out);
}

void vertex_normal_samples(const Scene& scene, int instance, uint32_t vertex, const vec3& normal,
                           const VertexRing& ring, int count, uint64_t seed,
                           std::vector<vec3>& out) {
  out.clear();
  const Instance& inst = scene.instances[size_t(instance)];
  const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
  const Material* material = nullptr;
  const Image* map = point_map(scene, mesh, &material);
  const uint32_t begin = ring.first[vertex], end = ring.first[vertex + 1];
  if (!map || begin == end) return;
  const vec4 t4 = mesh.tangents[vertex];
  vec3 t = glm::mat3(inst.transform) * vec3(t4);
  t -= normal * glm::dot(normal, t);
  const float len = glm::length(t);
  if (!(len > 1e-6f) || !std::isfinite(len)) return;
  t /= len;
  const vec3 b = glm::cross(normal, t) * (t4.w < 0.0f ? -1.0f : 1.0f);
  // The hat's integral over each adjacent triangle is a third of its area (object space:
  // the transform scales every triangle of a mesh alike up to shear, which we ignore).
  std::vector<double> cumulative(end - begin);
  double total = 0.0;
  for (uint32_t r = begin; r < end; ++r) {
    const uint32_t* idx = &mesh.indices[size_t(ring.triangles[r]) * 3];
    total += double(glm::length(glm::cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                           mesh.positions[idx[2]] - mesh.positions[idx[0]])));
    cumulative[r - begin] = total;
  }
  std::vector<vec2> uv0(static_cast<size_t>(count));
  SobolSampler sampler(seed);
  for (int k = 0; k < count; ++k) {
    sampler.start_sample(uint32_t(k));
    const double pick = double(sampler.next_1d()) * total;
    const size_t r =
        size_t(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    const uint32_t* idx =
        &mesh.indices[size_t(ring.triangles[begin + std::min(r, cumulative.size() - 1)]) * 3];
    // λ of the vertex ~ Beta(2, 2): the inverse of F(x) = 3x² − 2x³ is ½ + sin(asin(2u − 1)/3)
    // (sin 3φ = 3 sin φ − 4 sin³ φ); the other two split 1 − λ uniformly.
    const vec2 u = sampler.next_2d();
    const float lambda = 0.5f + std::sin(std::asin(2.0f * u.x - 1.0f) / 3.0f);
    int self = 0;
    while (self < 2 && idx[self] != vertex) ++self;
    const uint32_t o1 = idx[(self + 1) % 3], o2 = idx[(self + 2) % 3];
    uv0[size_t(k)] = lambda * mesh.uv0[vertex] + (1.0f - lambda) * u.y * mesh.uv0[o1] +
                     (1.0f - lambda) * (1.0f - u.y) * mesh.uv0[o2];
  }
  read_normals(*map, *material, uv0, t, b, normal, out);
}

}  // namespace illum::bake
