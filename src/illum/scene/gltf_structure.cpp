#include "illum/scene/gltf_structure.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/ranges.h>

#include "illum/core/error.h"
#include "illum/core/json_input.h"
#include "illum/scene/loaders.h"

namespace illum::detail {

namespace {

using nlohmann::json;

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;
constexpr uint32_t kChunkBin = 0x004E4942;
constexpr size_t kGlbHeaderBytes = 12, kChunkHeaderBytes = 8;

uint32_t read_u32_le(const std::string& bytes, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(bytes[at + i]);
  return v;
}

// The same decoding tinygltf applies before opening a buffer file, so both look for one file.
std::string percent_decoded(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return c >= 'a' && c <= 'f' ? c - 'a' + 10 : 0;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && i + 2 < uri.size()) {
      out += static_cast<char>((hex(uri[i + 1]) << 4) | hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// Bytes tinygltf's base64 decoder makes of a data URI: it stops at the first '=' or
// character outside the alphabet.
std::optional<uint64_t> data_uri_bytes(const std::string& uri) {
  const std::string marker = ";base64,";
  const size_t at = uri.find(marker);
  if (at == std::string::npos) return std::nullopt;
  uint64_t k = 0;
  for (size_t i = at + marker.size(); i < uri.size(); ++i, ++k) {
    const char c = uri[i];
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/')) break;
  }
  return k / 4 * 3 + (k % 4 == 2 ? 1 : k % 4 == 3 ? 2 : 0);
}

struct GlbChunks {
  std::string json;
  std::optional<uint64_t> bin_bytes;  // absent: no BIN chunk
};

GlbChunks split_glb(const std::string& bytes, const std::string& path) {
  auto fail = [&](const std::string& what) -> void {
    throw Error(fmt::format("{}: invalid GLB: {}", path, what));
  };
  if (bytes.size() < kGlbHeaderBytes + kChunkHeaderBytes)
    fail(fmt::format("{} bytes is too short for the header and a JSON chunk", bytes.size()));
  if (read_u32_le(bytes, 0) != kGlbMagic) fail("no 'glTF' magic at the start");
  if (const uint32_t version = read_u32_le(bytes, 4); version != 2)
    fail(fmt::format("container version {} (only 2 exists)", version));
  const uint64_t length = read_u32_le(bytes, 8);
  if (length > bytes.size() || length < kGlbHeaderBytes + kChunkHeaderBytes)
    fail(fmt::format("the header declares {} bytes, the file has {}", length, bytes.size()));
  const uint64_t json_bytes = read_u32_le(bytes, 12);
  if (read_u32_le(bytes, 16) != kChunkJson) fail("the first chunk is not JSON");
  const uint64_t json_start = kGlbHeaderBytes + kChunkHeaderBytes;
  if (json_bytes > length - json_start)
    fail(fmt::format("the JSON chunk of {} bytes runs past the {} bytes of the file", json_bytes,
                     length));
  GlbChunks chunks;
  chunks.json = bytes.substr(json_start, json_bytes);
  const uint64_t bin_header = json_start + json_bytes;
  const uint64_t rest = length - bin_header;
  if (rest == 0) return chunks;
  if (rest < kChunkHeaderBytes) fail(fmt::format("{} stray bytes after the JSON chunk", rest));
  const uint64_t bin_bytes = read_u32_le(bytes, bin_header);
  if (read_u32_le(bytes, bin_header + 4) != kChunkBin) fail("the second chunk is not BIN");
  if (bin_bytes > rest - kChunkHeaderBytes)
    fail(fmt::format("the BIN chunk of {} bytes runs past the {} bytes of the file", bin_bytes,
                     length));
  chunks.bin_bytes = bin_bytes;
  return chunks;
}

struct ViewExtent {
  uint64_t length = 0;
  uint64_t stride = 0;  // 0: tightly packed
};

class StructureChecker {
 public:
  StructureChecker(const std::string& path, const json& doc, bool binary,
                   std::optional<uint64_t> bin_bytes)
      : path_(path), doc_(doc), binary_(binary), bin_bytes_(bin_bytes) {}

  // Returns the bytes of the external buffer files.
  uint64_t run() {
    if (!doc_.is_object()) fail("the glTF top level must be a JSON object");
    const json* asset = member(doc_, "asset");
    if (asset == nullptr || !asset->is_object() || !asset->contains("version"))
      fail("glTF is missing the required 'asset.version'");
    check_required_extensions();
    reference(doc_, "scene", "scene", "scenes");
    check_buffers();
    check_buffer_views();
    check_accessors();
    check_scenes_and_nodes();
    check_meshes();
    check_textures_and_images();
    check_materials();
    check_lights_and_cameras();
    return external_bytes_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(fmt::format("{}: {}", path_, what));
  }

  static const json* member(const json& o, const char* key) {
    const auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
  }

  // A top-level array's length (0 when absent). Lights live inside an extension.
  size_t count_of(const char* array) const {
    const json* a = std::string(array) == "lights" ? light_list() : member(doc_, array);
    return a != nullptr && a->is_array() ? a->size() : 0;
  }

  const json* light_list() const {
    const json* ext = member(doc_, "extensions");
    if (ext == nullptr || !ext->is_object()) return nullptr;
    const json* lights = member(*ext, "KHR_lights_punctual");
    return lights != nullptr && lights->is_object() ? member(*lights, "lights") : nullptr;
  }

  // The elements of `o[key]`, which must be an array of objects when present.
  const json& objects(const json& o, const char* key, const std::string& where) const {
    static const json kEmpty = json::array();
    const json* a = member(o, key);
    if (a == nullptr) return kEmpty;
    if (!a->is_array()) fail(fmt::format("'{}' must be an array", where));
    for (size_t i = 0; i < a->size(); ++i) {
      if (!(*a)[i].is_object()) fail(fmt::format("{}[{}] must be a JSON object", where, i));
    }
    return *a;
  }

  // A non-negative integer `o[key]`; `fallback` when absent (required when there is none).
  uint64_t size_value(const json& o, const char* key, const std::string& where,
                      std::optional<uint64_t> fallback) const {
    const json* v = member(o, key);
    if (v == nullptr) {
      if (!fallback) fail(fmt::format("{} has no '{}'", where, key));
      return *fallback;
    }
    if (!v->is_number_unsigned())
      fail(fmt::format("{}.{} = {} must be a non-negative integer", where, key, v->dump()));
    return v->get<uint64_t>();
  }

  // An index into the top-level array `target`: an integer naming an element that exists.
  void index_value(const json& v, const std::string& where, const char* target) const {
    if (!v.is_number_unsigned())
      fail(fmt::format("{} = {} must be an index (a non-negative integer)", where, v.dump()));
    const size_t n = count_of(target);
    if (v.get<uint64_t>() >= n)
      fail(fmt::format("{} = {} refers to {}[{}], but the file has {} {}", where, v.dump(), target,
                       v.dump(), n, target));
  }

  // `o[key]` as an index into `target`; -1 when absent.
  int64_t reference(const json& o, const char* key, const std::string& where,
                    const char* target) const {
    const json* v = member(o, key);
    if (v == nullptr) return -1;
    index_value(*v, where, target);
    return static_cast<int64_t>(v->get<uint64_t>());
  }

  void check_required_extensions() const {
    const json* required = member(doc_, "extensionsRequired");
    if (required == nullptr) return;
    if (!required->is_array()) fail("'extensionsRequired' must be an array of names");
    const auto& supported = supported_gltf_extensions();
    for (const json& name : *required) {
      if (!name.is_string()) fail("'extensionsRequired' must be an array of names");
      const std::string s = name.get<std::string>();
      if (std::find(supported.begin(), supported.end(), s) == supported.end())
        fail(fmt::format("requires extension '{}', which illum does not support (supported: {})", s,
                         fmt::join(supported, ", ")));
    }
  }

  void check_buffers() {
    const json& buffers = objects(doc_, "buffers", "buffers");
    const std::string dir = parent_dir(path_);
    for (size_t i = 0; i < buffers.size(); ++i) {
      const json& b = buffers[i];
      const std::string where = fmt::format("buffers[{}]", i);
      const uint64_t declared = size_value(b, "byteLength", where, std::nullopt);
      if (declared == 0) fail(fmt::format("{}.byteLength must be at least 1", where));
      const json* uri = member(b, "uri");
      if (uri != nullptr && !uri->is_string()) fail(fmt::format("{}.uri must be a string", where));
      if (uri == nullptr) {
        if (!binary_) fail(fmt::format("{} has no 'uri' (only a .glb may omit it)", where));
        if (!bin_bytes_)
          fail(fmt::format("{} refers to the GLB's BIN chunk, but the file has none", where));
        if (declared > *bin_bytes_)
          fail(fmt::format("{}.byteLength = {}, but the GLB's BIN chunk has {} bytes", where,
                           declared, *bin_bytes_));
      } else if (const std::string u = uri->get<std::string>(); u.rfind("data:", 0) == 0) {
        const auto decoded = data_uri_bytes(u);
        if (!decoded) fail(fmt::format("{} has a data URI that is not base64", where));
        if (*decoded != declared)
          fail(fmt::format("{}.byteLength = {}, but its data URI holds {} bytes", where, declared,
                           *decoded));
      } else {
        const std::string file = join_path(dir, percent_decoded(u));
        if (!file_exists(file))
          fail(fmt::format("missing buffer '{}' ({}): file not found", u, where));
        std::error_code ec;
        const uint64_t actual = std::filesystem::file_size(file, ec);
        if (ec) fail(fmt::format("cannot read buffer '{}' ({}): {}", u, where, ec.message()));
        if (actual != declared)
          fail(
              fmt::format("{}.byteLength = {}, but '{}' has {} bytes", where, declared, u, actual));
        external_bytes_ += actual;
      }
      buffer_bytes_.push_back(declared);
    }
  }

  void check_buffer_views() {
    const json& views = objects(doc_, "bufferViews", "bufferViews");
    for (size_t i = 0; i < views.size(); ++i) {
      const json& v = views[i];
      const std::string where = fmt::format("bufferViews[{}]", i);
      const json* buffer = member(v, "buffer");
      if (buffer == nullptr) fail(fmt::format("{} has no 'buffer'", where));
      index_value(*buffer, where + ".buffer", "buffers");
      const uint64_t size = buffer_bytes_[buffer->get<uint64_t>()];
      const uint64_t offset = size_value(v, "byteOffset", where, 0);
      const uint64_t length = size_value(v, "byteLength", where, std::nullopt);
      if (length == 0) fail(fmt::format("{}.byteLength must be at least 1", where));
      if (offset > size || length > size - offset)
        fail(
            fmt::format("{} (byteOffset {} + byteLength {}) runs past the end of buffers[{}] ({} "
                        "bytes)",
                        where, offset, length, buffer->get<uint64_t>(), size));
      const uint64_t stride = size_value(v, "byteStride", where, 0);
      if (member(v, "byteStride") != nullptr && (stride < 4 || stride > 252 || stride % 4 != 0))
        fail(fmt::format("{}.byteStride = {} must be a multiple of 4 in [4, 252]", where, stride));
      views_.push_back({length, stride});
    }
  }

  void check_accessors() const {
    static const std::map<uint64_t, uint64_t> kComponentBytes = {{5120, 1}, {5121, 1}, {5122, 2},
                                                                 {5123, 2}, {5125, 4}, {5126, 4}};
    static const std::map<std::string, uint64_t> kComponents = {
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
        {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
    const json& accessors = objects(doc_, "accessors", "accessors");
    for (size_t i = 0; i < accessors.size(); ++i) {
      const json& a = accessors[i];
      const std::string where = fmt::format("accessors[{}]", i);
      const uint64_t component_type = size_value(a, "componentType", where, std::nullopt);
      const auto bytes = kComponentBytes.find(component_type);
      if (bytes == kComponentBytes.end())
        fail(fmt::format("{}.componentType = {} is not a glTF component type", where,
                         component_type));
      const json* type = member(a, "type");
      const auto comps = type != nullptr && type->is_string()
                             ? kComponents.find(type->get<std::string>())
                             : kComponents.end();
      if (comps == kComponents.end())
        fail(fmt::format("{}.type must be one of SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4",
                         where));
      const uint64_t count = size_value(a, "count", where, std::nullopt);
      if (count == 0) fail(fmt::format("{}.count must be at least 1", where));
      const uint64_t offset = size_value(a, "byteOffset", where, 0);
      const int64_t view = reference(a, "bufferView", where + ".bufferView", "bufferViews");
      if (view < 0) continue;  // all zeros (or sparse): the reader charges what it decodes
      const uint64_t element = bytes->second * comps->second;
      const ViewExtent& extent = views_[static_cast<size_t>(view)];
      if (extent.stride != 0 && extent.stride < element)
        fail(
            fmt::format("{} has {}-byte elements, longer than the byteStride {} of "
                        "bufferViews[{}]",
                        where, element, extent.stride, view));
      const uint64_t stride = extent.stride != 0 ? extent.stride : element;
      // offset + (count − 1)·stride + element ≤ view length, without overflow.
      const bool fits = offset <= extent.length && element <= extent.length - offset &&
                        count - 1 <= (extent.length - offset - element) / stride;
      if (!fits)
        fail(
            fmt::format("{} ({} elements of {} bytes, stride {}, from byteOffset {}) reads past "
                        "the end of bufferViews[{}] ({} bytes)",
                        where, count, element, stride, offset, view, extent.length));
    }
  }

  void check_scenes_and_nodes() const {
    const json& scenes = objects(doc_, "scenes", "scenes");
    for (size_t i = 0; i < scenes.size(); ++i)
      index_list(scenes[i], "nodes", fmt::format("scenes[{}].nodes", i), "nodes");
    const json& nodes = objects(doc_, "nodes", "nodes");
    for (size_t i = 0; i < nodes.size(); ++i) {
      const json& n = nodes[i];
      const std::string where = fmt::format("nodes[{}]", i);
      index_list(n, "children", where + ".children", "nodes");
      reference(n, "mesh", where + ".mesh", "meshes");
      reference(n, "camera", where + ".camera", "cameras");
      reference(n, "skin", where + ".skin", "skins");
      // tinygltf ignores TRS beside a matrix and any array of the wrong shape, silently.
      numbers(n, "matrix", 16, where);
      numbers(n, "translation", 3, where);
      numbers(n, "rotation", 4, where);
      numbers(n, "scale", 3, where);
      if (n.contains("matrix") &&
          (n.contains("translation") || n.contains("rotation") || n.contains("scale")))
        fail(fmt::format("{} has both a matrix and translation/rotation/scale", where));
      const json* ext = member(n, "extensions");
      const json* light =
          ext != nullptr && ext->is_object() ? member(*ext, "KHR_lights_punctual") : nullptr;
      if (light == nullptr) continue;
      const std::string lw = where + ".extensions.KHR_lights_punctual.light";
      if (!light->is_object() || !light->contains("light")) fail(fmt::format("{} is missing", lw));
      index_value((*light)["light"], lw, "lights");
    }
  }

  // `o[key]`, when present, must be a number: tinygltf would keep its default without a word.
  void number(const json& o, const char* key, const std::string& where) const {
    const json* v = member(o, key);
    if (v != nullptr && !v->is_number())
      fail(fmt::format("{}.{} = {} must be a number", where, key, v->dump()));
  }

  // `o[key]`, when present, must be an array of exactly `n` numbers.
  void numbers(const json& o, const char* key, size_t n, const std::string& where) const {
    const json* v = member(o, key);
    if (v == nullptr) return;
    bool ok = v->is_array() && v->size() == n;
    for (size_t i = 0; ok && i < n; ++i) ok = (*v)[i].is_number();
    if (!ok) fail(fmt::format("{}.{} must be an array of {} numbers", where, key, n));
  }

  void check_lights_and_cameras() const {
    const json* list = light_list();
    if (list != nullptr) {
      if (!list->is_array()) fail("extensions.KHR_lights_punctual.lights must be an array");
      for (size_t i = 0; i < list->size(); ++i) {
        const json& l = (*list)[i];
        const std::string where = fmt::format("KHR_lights_punctual lights[{}]", i);
        if (!l.is_object()) fail(fmt::format("{} must be a JSON object", where));
        numbers(l, "color", 3, where);
        number(l, "intensity", where);
        number(l, "range", where);
        if (const json* spot = member(l, "spot"); spot != nullptr && spot->is_object()) {
          number(*spot, "innerConeAngle", where + ".spot");
          number(*spot, "outerConeAngle", where + ".spot");
        }
      }
    }
    const json& cameras = objects(doc_, "cameras", "cameras");
    for (size_t i = 0; i < cameras.size(); ++i) {
      for (const char* type : {"perspective", "orthographic"}) {
        const json* c = member(cameras[i], type);
        if (c == nullptr || !c->is_object()) continue;
        const std::string where = fmt::format("cameras[{}].{}", i, type);
        for (const char* key : {"yfov", "znear", "zfar", "aspectRatio", "xmag", "ymag"})
          number(*c, key, where);
      }
    }
  }

  void index_list(const json& o, const char* key, const std::string& where,
                  const char* target) const {
    const json* list = member(o, key);
    if (list == nullptr) return;
    if (!list->is_array()) fail(fmt::format("{} must be an array of indices", where));
    for (size_t k = 0; k < list->size(); ++k)
      index_value((*list)[k], fmt::format("{}[{}]", where, k), target);
  }

  void check_meshes() const {
    const json& meshes = objects(doc_, "meshes", "meshes");
    for (size_t m = 0; m < meshes.size(); ++m) {
      const std::string mw = fmt::format("meshes[{}]", m);
      const json& primitives = objects(meshes[m], "primitives", mw + ".primitives");
      for (size_t p = 0; p < primitives.size(); ++p) {
        const json& prim = primitives[p];
        const std::string where = fmt::format("{}.primitives[{}]", mw, p);
        const json* attributes = member(prim, "attributes");
        if (attributes == nullptr || !attributes->is_object())
          fail(fmt::format("{}.attributes must be an object", where));
        for (const auto& [name, value] : attributes->items())
          index_value(value, fmt::format("{}.attributes.{}", where, name), "accessors");
        reference(prim, "indices", where + ".indices", "accessors");
        reference(prim, "material", where + ".material", "materials");
        const uint64_t mode = size_value(prim, "mode", where, 4);
        if (mode > 6) fail(fmt::format("{}.mode = {} is not a glTF primitive mode", where, mode));
      }
    }
  }

  void check_textures_and_images() const {
    const json& textures = objects(doc_, "textures", "textures");
    for (size_t i = 0; i < textures.size(); ++i) {
      const std::string where = fmt::format("textures[{}]", i);
      reference(textures[i], "source", where + ".source", "images");
      reference(textures[i], "sampler", where + ".sampler", "samplers");
    }
    const json& images = objects(doc_, "images", "images");
    for (size_t i = 0; i < images.size(); ++i)
      reference(images[i], "bufferView", fmt::format("images[{}].bufferView", i), "bufferViews");
  }

  void check_materials() const {
    const json& materials = objects(doc_, "materials", "materials");
    for (size_t i = 0; i < materials.size(); ++i) {
      const json& m = materials[i];
      const std::string where = fmt::format("materials[{}]", i);
      texture_info(m, "normalTexture", where);
      texture_info(m, "occlusionTexture", where);
      texture_info(m, "emissiveTexture", where);
      numbers(m, "emissiveFactor", 3, where);
      number(m, "alphaCutoff", where);
      if (const json* pbr = member(m, "pbrMetallicRoughness")) {
        if (!pbr->is_object())
          fail(fmt::format("{}.pbrMetallicRoughness must be an object", where));
        const std::string pw = where + ".pbrMetallicRoughness";
        numbers(*pbr, "baseColorFactor", 4, pw);
        number(*pbr, "metallicFactor", pw);
        number(*pbr, "roughnessFactor", pw);
        texture_info(*pbr, "baseColorTexture", where + ".pbrMetallicRoughness");
        texture_info(*pbr, "metallicRoughnessTexture", where + ".pbrMetallicRoughness");
      }
    }
  }

  void texture_info(const json& o, const char* key, const std::string& parent) const {
    const json* info = member(o, key);
    if (info == nullptr) return;
    const std::string where = fmt::format("{}.{}", parent, key);
    if (!info->is_object() || !info->contains("index"))
      fail(fmt::format("{} must be an object with an 'index'", where));
    index_value((*info)["index"], where + ".index", "textures");
    size_value(*info, "texCoord", where, 0);
    number(*info, "scale", where);
    number(*info, "strength", where);
  }

  const std::string& path_;
  const json& doc_;
  const bool binary_;
  const std::optional<uint64_t> bin_bytes_;
  uint64_t external_bytes_ = 0;
  std::vector<uint64_t> buffer_bytes_;
  std::vector<ViewExtent> views_;
};

}  // namespace

const std::vector<std::string>& supported_gltf_extensions() {
  static const std::vector<std::string> kSupported = {
      "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior",
      "KHR_materials_transmission", "KHR_mesh_quantization"};
  return kSupported;
}

GltfStructure check_gltf_structure(const std::string& path) {
  const std::string bytes = read_file_bytes(path);
  const bool binary = lower_extension(path) == ".glb";
  GltfStructure out;
  std::optional<uint64_t> bin_bytes;
  if (binary) {
    GlbChunks chunks = split_glb(bytes, path);
    out.json = parse_json(chunks.json, path);
    bin_bytes = chunks.bin_bytes;
  } else {
    out.json = parse_json(bytes, path);
  }
  out.input_bytes = bytes.size() + StructureChecker(path, out.json, binary, bin_bytes).run();
  return out;
}

}  // namespace illum::detail
