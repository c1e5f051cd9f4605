// Decoding glTF accessors under the loader's decode budget (gltf_accessors.h).
#include "illum/scene/gltf_accessors.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "illum/core/error.h"

namespace illum::detail {

GltfAccessors::GltfAccessors(const std::string& path, const tinygltf::Model& model,
                             uint64_t input_bytes)
    : path_(path),
      model_(model),
      input_bytes_(input_bytes),
      budget_left_(kDecodeExpansion * input_bytes + kDecodeAllowanceBytes) {}

void GltfAccessors::fail(const std::string& what) const {
  throw Error(fmt::format("{}: {}", path_, what));
}

// Takes `count` items of `item_bytes` each from the decode budget before they are
// allocated (the product is never formed: a declared count may be near 2⁶⁴).
void GltfAccessors::charge(uint64_t count, uint64_t item_bytes, const std::string& what) {
  if (count > budget_left_ / item_bytes)
    fail(fmt::format(
        "{} would decode {} items of {} bytes, past the decode budget ({} × the {} "
        "input bytes + {} MiB): the file declares far more data than it holds",
        what, count, item_bytes, kDecodeExpansion, input_bytes_, kDecodeAllowanceBytes >> 20));
  budget_left_ -= count * item_bytes;
}

const tinygltf::Accessor& GltfAccessors::accessor(int index, const std::string& what) const {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
    fail(fmt::format("{} refers to accessor {}, which does not exist", what, index));
  return model_.accessors[index];
}

// Decodes `want` floats per element of accessor `index` into `out`, for the elements listed
// in `subset` (all of them when it is null), honouring byte strides and normalized integer
// types. Indices go through read_indices instead.
void GltfAccessors::read_attribute(int index, int want, const std::string& what,
                                   const std::vector<uint32_t>* subset, std::vector<float>& out) {
  const tinygltf::Accessor& acc = accessor(index, what);
  const int comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
  if (comps != want)
    fail(
        fmt::format("{} (accessors[{}]) has {} components, expected {}", what, index, comps, want));
  if (acc.sparse.isSparse)
    fail(fmt::format("{} (accessors[{}]) is sparse, which is not supported", what, index));
  const size_t n = subset != nullptr ? subset->size() : acc.count;
  charge(n, want * sizeof(float), what);
  out.assign(n * static_cast<size_t>(want), 0.0f);
  if (acc.bufferView < 0) return;  // all zeros by the spec
  const unsigned char* base = element_base(acc, index, what);
  const size_t csize = static_cast<size_t>(
      tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType)));
  const size_t stride = element_stride(acc);
  for (size_t k = 0; k < n; ++k) {
    const size_t e = subset != nullptr ? (*subset)[k] : k;
    const unsigned char* p = base + e * stride;
    for (int c = 0; c < want; ++c) {
      out[k * want + c] = component(p + c * csize, acc.componentType, acc.normalized);
    }
  }
}

// The indices of accessor `index`, each checked against the `vertex_count` they index.
std::vector<uint32_t> GltfAccessors::read_indices(int index, size_t vertex_count,
                                                  const std::string& what) {
  const tinygltf::Accessor& acc = accessor(index, what);
  if (acc.type != TINYGLTF_TYPE_SCALAR || acc.bufferView < 0)
    fail(
        fmt::format("{} (accessors[{}]) must be a scalar accessor with a bufferView", what, index));
  charge(acc.count, sizeof(uint32_t), what);
  const unsigned char* base = element_base(acc, index, what);
  const size_t stride = element_stride(acc);
  std::vector<uint32_t> out(acc.count);
  for (size_t e = 0; e < acc.count; ++e) {
    const unsigned char* p = base + e * stride;
    switch (acc.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        out[e] = *p;
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        out[e] = v;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        std::memcpy(&out[e], p, 4);
        break;
      default:
        fail(fmt::format("{} (accessors[{}]) has component type {}, not an unsigned integer", what,
                         index, acc.componentType));
    }
    if (out[e] >= vertex_count)
      fail(fmt::format("{} (accessors[{}]) entry {} is vertex {}, past the {} vertices", what,
                       index, e, out[e], vertex_count));
  }
  return out;
}

size_t GltfAccessors::element_stride(const tinygltf::Accessor& acc) const {
  const int stride = acc.ByteStride(model_.bufferViews[acc.bufferView]);
  return stride > 0 ? static_cast<size_t>(stride) : 0;
}

// Start of the accessor's data, after checking (again: gltf_structure.cpp did it on the
// JSON) that all of it lies inside its view and the buffer tinygltf loaded.
const unsigned char* GltfAccessors::element_base(const tinygltf::Accessor& acc, int index,
                                                 const std::string& what) const {
  if (static_cast<size_t>(acc.bufferView) >= model_.bufferViews.size())
    fail(fmt::format("{} (accessors[{}]) refers to bufferView {}, which does not exist", what,
                     index, acc.bufferView));
  const tinygltf::BufferView& view = model_.bufferViews[acc.bufferView];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model_.buffers.size())
    fail(fmt::format("bufferViews[{}] refers to buffer {}, which does not exist", acc.bufferView,
                     view.buffer));
  const tinygltf::Buffer& buffer = model_.buffers[view.buffer];
  const int stride = acc.ByteStride(view);
  if (stride <= 0)
    fail(fmt::format("{} (accessors[{}]) has an invalid type or byte stride", what, index));
  const size_t elem =
      static_cast<size_t>(
          tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType))) *
      static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type)));
  const size_t view_end = std::min(view.byteOffset + view.byteLength, buffer.data.size());
  const size_t start = view.byteOffset + acc.byteOffset;
  const bool fits = acc.count > 0 && start <= view_end && elem <= view_end - start &&
                    acc.count - 1 <= (view_end - start - elem) / static_cast<size_t>(stride);
  if (!fits)
    fail(fmt::format("{} (accessors[{}]) reads past the end of bufferViews[{}]", what, index,
                     acc.bufferView));
  return buffer.data.data() + start;
}

float GltfAccessors::component(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = *p;
      return normalized ? v / 255.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float v = static_cast<float>(static_cast<int8_t>(*p));
      return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? static_cast<float>(v) / 65535.0f : static_cast<float>(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(static_cast<float>(v) / 32767.0f, -1.0f) : static_cast<float>(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return static_cast<float>(v);
    }
    default:
      return 0.0f;
  }
}

}  // namespace illum::detail
