// Internal to the glTF loader: accessors (vertex attributes, indices) decoded into floats and
// 32-bit indices, every element's range checked against the buffer tinygltf loaded, and every
// decoded byte charged against a budget proportional to the input.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace illum::detail {

// Decoded geometry (vertex attributes as floats, indices as 32-bit integers, instances) may
// take at most kDecodeExpansion times the bytes of the input — the file and its buffer files
// — plus kDecodeAllowanceBytes. Honest files stay well inside: an attribute widens at most
// 4× (a normalized byte becomes a float), and primitives that share a vertex accessor keep
// only the vertices their indices use. A file that declares far more than it holds (a huge
// count on an accessor without bufferView, one accessor read by thousands of primitives, a
// mesh of many primitives under thousands of nodes) stops with an error instead.
inline constexpr uint64_t kDecodeExpansion = 16;
inline constexpr uint64_t kDecodeAllowanceBytes = uint64_t{64} << 20;

// Errors are illum::Error "<path>: <what> (accessors[i]) ...".
class GltfAccessors {
 public:
  GltfAccessors(const std::string& path, const tinygltf::Model& model, uint64_t input_bytes);

  // Takes `count` items of `item_bytes` each from the decode budget before they are
  // allocated (the product is never formed: a declared count may be near 2⁶⁴).
  void charge(uint64_t count, uint64_t item_bytes, const std::string& what);
  const tinygltf::Accessor& accessor(int index, const std::string& what) const;
  // Decodes `want` floats per element of accessor `index` into `out`, for the elements listed
  // in `subset` (all of them when it is null), honouring byte strides and normalized integer
  // types.
  void read_attribute(int index, int want, const std::string& what,
                      const std::vector<uint32_t>* subset, std::vector<float>& out);
  // The indices of accessor `index`, each checked against the `vertex_count` they index.
  std::vector<uint32_t> read_indices(int index, size_t vertex_count, const std::string& what);

 private:
  [[noreturn]] void fail(const std::string& what) const;
  size_t element_stride(const tinygltf::Accessor& acc) const;
  const unsigned char* element_base(const tinygltf::Accessor& acc, int index,
                                    const std::string& what) const;
  static float component(const unsigned char* p, int type, bool normalized);

  const std::string& path_;
  const tinygltf::Model& model_;
  const uint64_t input_bytes_;
  uint64_t budget_left_;
};

}  // namespace illum::detail
