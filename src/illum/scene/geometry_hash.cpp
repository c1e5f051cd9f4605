#include "illum/scene/geometry_hash.h"

#include <fmt/format.h>
#include <bit>

#include "illum/core/rng.h"

namespace illum {

namespace {

class Hasher {
 public:
  void add(uint64_t word) { h_ = hash_mix(h_, word); }
  void add(float v) { add(static_cast<uint64_t>(std::bit_cast<uint32_t>(v))); }
  template <int N>
  void add(const glm::vec<N, float>& v) {
    for (int i = 0; i < N; ++i) add(v[i]);
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 0x696c6c756d2d6731ULL;  // "illum-g1": a new layout gets a new start value
};

}  // namespace

uint64_t geometry_hash(const Scene& scene) {
  Hasher h;
  h.add(uint64_t{scene.meshes.size()});
  for (const Mesh& mesh : scene.meshes) {
    h.add(uint64_t{mesh.positions.size()});
    const bool tangents = mesh.tangents.size() == mesh.positions.size();
    const bool uv1 = mesh.uv1.size() == mesh.positions.size();
    h.add(uint64_t{tangents} | uint64_t{uv1} << 1);
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      h.add(mesh.positions[v]);
      if (v < mesh.normals.size()) h.add(mesh.normals[v]);
      if (tangents) h.add(mesh.tangents[v]);
      if (uv1) h.add(mesh.uv1[v]);
    }
    h.add(uint64_t{mesh.indices.size()});
    for (const uint32_t i : mesh.indices) h.add(uint64_t{i});
  }
  h.add(uint64_t{scene.instances.size()});
  for (const Instance& instance : scene.instances) {
    h.add(static_cast<uint64_t>(static_cast<int64_t>(instance.mesh)));
    for (int c = 0; c < 4; ++c) h.add(instance.transform[c]);
  }
  return h.value();
}

std::string geometry_hash_hex(const Scene& scene) {
  return fmt::format("{:016x}", geometry_hash(scene));
}

}  // namespace illum
