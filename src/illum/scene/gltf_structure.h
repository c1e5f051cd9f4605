// Internal to the glTF loader: what is checked on a .gltf or .glb before tinygltf parses it.
// tinygltf trusts declared sizes (it reads an image from a bufferView without checking that
// the view lies inside its buffer), silently reads a negative byteOffset or byteStride as
// absent, truncates indices past 2³¹ and recurses once per nesting level of "extensions" and
// "extras"; so every count, offset, stride and index the loader relies on is checked here
// against the bytes that exist, on our own parse of the JSON, before anything is allocated
// on the file's word.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace illum::detail {

struct GltfStructure {
  nlohmann::json json;       // the document (a .glb's JSON chunk)
  uint64_t input_bytes = 0;  // the file plus its external buffer files: the decode budget's base
};

// Reads `path` and checks, throwing Error "<path>: <element> ..." on the first problem:
// * a .glb's header and chunk lengths against the file size (JSON chunk first, BIN second);
// * the JSON: nesting depth (core/json_input.h), syntax, numbers beyond a double;
// * asset.version; every name in extensionsRequired is one illum implements;
// * "scene" and every index the loader follows (scenes, nodes, meshes, primitives, accessors,
//   bufferViews, buffers, materials, textures, images, samplers, cameras, lights) is an
//   integer naming an element that exists;
// * buffers: byteLength ≥ 1 and equal to the bytes that exist (a data URI's decoded size, an
//   external file's size, at most the GLB BIN chunk); an external file that is absent is
//   "missing buffer 'x.bin' (buffers[i]): file not found";
// * bufferViews: byteOffset + byteLength inside the buffer, byteStride in [4, 252] and a
//   multiple of 4;
// * accessors: componentType, type and count ≥ 1 valid; with a bufferView, a byteStride no
//   shorter than one element and the last element inside the view;
// * the numbers the loader reads (factors, node matrix/TRS, light and camera values) are
//   numbers, arrays have their glTF length, and a node has a matrix or TRS, not both.
//   Their ranges are checked after parsing, in gltf_loader.cpp.
GltfStructure check_gltf_structure(const std::string& path);

// The extensions whose meaning illum implements (or which change nothing it reads).
const std::vector<std::string>& supported_gltf_extensions();

}  // namespace illum::detail
