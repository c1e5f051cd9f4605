// glTF 2.0 (.gltf, .glb) through tinygltf. Node transforms become instances, primitives
// meshes, metallic-roughness materials map onto illum's material types (mapping below and in
// docs/scene-format.md), KHR_lights_punctual lights become point/spot/directional lights and
// the first perspective camera in the node tree becomes Scene::camera.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <span>

#include <tiny_gltf.h>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/loaders.h"
#include "illum/scene/mesh_processing.h"

namespace illum::detail {

namespace {

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  std::replace(s.begin(), s.end(), '\n', ';');
  return s;
}

// Catches what tinygltf reports badly or not at all before handing the file over: malformed
// JSON (with line and column), a missing "asset", and external buffers that are not there
// (Sponza without its .bin must fail with "missing buffer", not half-load).
void precheck_gltf_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(fmt::format("{}: cannot open file", path));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    const auto pos = what.find("] ");
    throw Error(fmt::format("{}: malformed glTF JSON: {}", path,
                            pos == std::string::npos ? what : what.substr(pos + 2)));
  }
  if (!j.is_object()) throw Error(fmt::format("{}: glTF top level must be a JSON object", path));
  if (!j.contains("asset") || !j["asset"].is_object() || !j["asset"].contains("version"))
    throw Error(fmt::format("{}: glTF is missing the required 'asset.version'", path));
  if (j.contains("buffers") && j["buffers"].is_array()) {
    const std::string dir = parent_dir(path);
    for (size_t i = 0; i < j["buffers"].size(); ++i) {
      const auto& b = j["buffers"][i];
      if (!b.is_object()) continue;
      if (!b.contains("uri") || !b["uri"].is_string())
        throw Error(fmt::format("{}: buffers[{}] has no 'uri' (only a .glb may omit it)", path, i));
      const std::string uri = b["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) continue;
      if (!file_exists(join_path(dir, uri)))
        throw Error(
            fmt::format("{}: missing buffer '{}' (buffers[{}]): file not found", path, uri, i));
    }
  }
}

double number(const tinygltf::Value& object, const std::string& key, double fallback) {
  if (!object.IsObject() || !object.Has(key)) return fallback;
  const tinygltf::Value& v = object.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

const tinygltf::Value* extension(const tinygltf::ExtensionMap& ext, const std::string& name) {
  auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}

class GltfReader {
 public:
  GltfReader(const std::string& path, const tinygltf::Model& model, Scene& scene,
             const LoadOptions& options, const std::map<int, std::vector<uint8_t>>& image_bytes)
      : path_(path), model_(model), scene_(scene), options_(options), image_bytes_(image_bytes) {}

  void read() {
    read_materials();
    read_meshes();
    read_nodes();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(fmt::format("{}: {}", path_, what));
  }

  // Reads `count` elements of `want` components each from an accessor as floats, honouring
  // byte strides and normalized integer types. Indices go through read_indices instead.
  std::vector<float> read_floats(int accessor_index, int want, const char* what) const {
    if (accessor_index < 0 || static_cast<size_t>(accessor_index) >= model_.accessors.size())
      fail(fmt::format("{} refers to accessor {}, which does not exist", what, accessor_index));
    const tinygltf::Accessor& acc = model_.accessors[accessor_index];
    const int comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
    if (comps != want)
      fail(fmt::format("accessors[{}] ({}) has {} components, expected {}", accessor_index, what,
                       comps, want));
    if (acc.sparse.isSparse)
      fail(fmt::format("accessors[{}] ({}) is sparse, which is not supported", accessor_index,
                       what));
    std::vector<float> out(acc.count * static_cast<size_t>(want), 0.0f);
    if (acc.bufferView < 0) return out;  // all zeros by the spec
    const unsigned char* base = element_base(acc, accessor_index, what);
    const size_t csize = static_cast<size_t>(
        tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType)));
    const size_t stride = element_stride(acc);
    for (size_t e = 0; e < acc.count; ++e) {
      const unsigned char* p = base + e * stride;
      for (int c = 0; c < want; ++c) {
        out[e * want + c] = component(p + c * csize, acc.componentType, acc.normalized);
      }
    }
    return out;
  }

  std::vector<uint32_t> read_indices(int accessor_index) const {
    if (accessor_index < 0 || static_cast<size_t>(accessor_index) >= model_.accessors.size())
      fail(fmt::format("indices refer to accessor {}, which does not exist", accessor_index));
    const tinygltf::Accessor& acc = model_.accessors[accessor_index];
    if (acc.type != TINYGLTF_TYPE_SCALAR || acc.bufferView < 0)
      fail(fmt::format("accessors[{}] (indices) must be a scalar accessor with a bufferView",
                       accessor_index));
    const unsigned char* base = element_base(acc, accessor_index, "indices");
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
          fail(fmt::format("accessors[{}] (indices) has component type {}, not an unsigned integer",
                           accessor_index, acc.componentType));
      }
    }
    return out;
  }

  size_t element_stride(const tinygltf::Accessor& acc) const {
    const int stride = acc.ByteStride(model_.bufferViews[acc.bufferView]);
    return stride > 0 ? static_cast<size_t>(stride) : 0;
  }

  // Start of the accessor's data, after checking that all of it lies inside its buffer.
  const unsigned char* element_base(const tinygltf::Accessor& acc, int index,
                                    const char* what) const {
    if (static_cast<size_t>(acc.bufferView) >= model_.bufferViews.size())
      fail(fmt::format("accessors[{}] ({}) refers to bufferView {}, which does not exist", index,
                       what, acc.bufferView));
    const tinygltf::BufferView& view = model_.bufferViews[acc.bufferView];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model_.buffers.size())
      fail(fmt::format("bufferViews[{}] refers to buffer {}, which does not exist", acc.bufferView,
                       view.buffer));
    const tinygltf::Buffer& buffer = model_.buffers[view.buffer];
    const int stride = acc.ByteStride(view);
    if (stride <= 0)
      fail(fmt::format("accessors[{}] ({}) has an invalid type or byte stride", index, what));
    const size_t elem =
        static_cast<size_t>(
            tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType))) *
        static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type)));
    const size_t start = view.byteOffset + acc.byteOffset;
    const size_t end = acc.count == 0 ? start : start + (acc.count - 1) * stride + elem;
    if (end > view.byteOffset + view.byteLength || end > buffer.data.size())
      fail(fmt::format("accessors[{}] ({}) reads past the end of buffer {} ({} > {} bytes)", index,
                       what, view.buffer, end, buffer.data.size()));
    return buffer.data.data() + start;
  }

  static float component(const unsigned char* p, int type, bool normalized) {
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
        return normalized ? std::max(static_cast<float>(v) / 32767.0f, -1.0f)
                          : static_cast<float>(v);
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

  // One illum texture per (glTF texture, encoding): base colour and emission are sRGB,
  // normal and metallic-roughness maps linear. Every image goes through illum's own checked
  // decoder (core/image.h): embedded (data: URI, GLB bufferView) or external. A missing or
  // undecodable image is an error naming it and the material (missing_texture: a warning
  // with allow_missing_textures); a bufferView past its buffer is a malformed file.
  int texture(int gltf_texture, bool srgb, const std::string& material) {
    if (!options_.load_textures || gltf_texture < 0) return kNoTexture;
    if (static_cast<size_t>(gltf_texture) >= model_.textures.size())
      fail(fmt::format("material '{}' refers to texture {}, which does not exist", material,
                       gltf_texture));
    const int source = model_.textures[gltf_texture].source;
    const auto key = std::make_pair(source, srgb);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    int id = kNoTexture;
    if (source < 0) {
      // The image is in an extension illum does not read (KHR_texture_basisu, EXT_texture_webp).
      missing_texture(scene_, options_,
                      fmt::format("{}: texture {} of material '{}' has no PNG or JPEG source",
                                  path_, gltf_texture, material));
    } else if (static_cast<size_t>(source) >= model_.images.size()) {
      fail(
          fmt::format("texture {} refers to image {}, which does not exist", gltf_texture, source));
    } else {
      const tinygltf::Image& img = model_.images[source];
      const bool external =
          img.bufferView < 0 && !img.uri.empty() && img.uri.rfind("data:", 0) != 0;
      const std::string name = external ? join_path(parent_dir(path_), img.uri)
                                        : fmt::format("{}: images[{}]", path_, source);
      std::span<const uint8_t> bytes;
      if (img.bufferView >= 0) {
        // tinygltf hands over bufferView images without checking the view against its buffer.
        if (static_cast<size_t>(img.bufferView) >= model_.bufferViews.size())
          fail(fmt::format("images[{}] refers to bufferView {}, which does not exist", source,
                           img.bufferView));
        const tinygltf::BufferView& view = model_.bufferViews[img.bufferView];
        if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model_.buffers.size() ||
            view.byteOffset > model_.buffers[view.buffer].data.size() ||
            view.byteLength > model_.buffers[view.buffer].data.size() - view.byteOffset)
          fail(
              fmt::format("images[{}]: bufferView {} ({} bytes at offset {}) lies outside its "
                          "buffer",
                          source, img.bufferView, view.byteLength, view.byteOffset));
        bytes = std::span<const uint8_t>(model_.buffers[view.buffer].data.data() + view.byteOffset,
                                         view.byteLength);
      } else if (auto it = image_bytes_.find(source); it != image_bytes_.end()) {
        bytes = it->second;
      }
      if (bytes.empty() && external && !file_exists(name)) {
        missing_texture(
            scene_, options_,
            fmt::format("{}: texture '{}' of material '{}' not found", path_, name, material));
      } else {
        try {
          Texture tex;
          tex.path = name;
          tex.srgb = srgb;
          tex.image = decode_image(bytes, name, srgb);  // an empty file is an error there
          id = static_cast<int>(scene_.textures.size());
          scene_.textures.push_back(std::move(tex));
        } catch (const Error& e) {
          missing_texture(
              scene_, options_,
              fmt::format("{}: texture of material '{}': {}", path_, material, e.what()));
        }
      }
    }
    textures_[key] = id;
    return id;
  }

  void read_materials() {
    for (const tinygltf::Material& gm : model_.materials) {
      Material m;
      m.name = gm.name;
      const auto& pbr = gm.pbrMetallicRoughness;
      Color base(1.0f);
      if (pbr.baseColorFactor.size() == 4) {
        base = Color(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
        m.opacity = static_cast<float>(pbr.baseColorFactor[3]);
      }
      m.albedo = base;
      m.albedo_texture = texture(pbr.baseColorTexture.index, true, m.name);
      const float metallic = static_cast<float>(pbr.metallicFactor);
      m.roughness = std::clamp(static_cast<float>(pbr.roughnessFactor), 0.0f, 1.0f);
      m.roughness_texture = texture(pbr.metallicRoughnessTexture.index, false, m.name);
      m.normal_texture = texture(gm.normalTexture.index, false, m.name);
      m.normal_scale = static_cast<float>(gm.normalTexture.scale);
      if (gm.emissiveFactor.size() == 3)
        m.emission = Color(gm.emissiveFactor[0], gm.emissiveFactor[1], gm.emissiveFactor[2]);
      m.emission_texture = texture(gm.emissiveTexture.index, true, m.name);
      if (const auto* e = extension(gm.extensions, "KHR_materials_emissive_strength"))
        m.emission *= static_cast<float>(number(*e, "emissiveStrength", 1.0));
      if (const auto* e = extension(gm.extensions, "KHR_materials_ior"))
        m.ior = static_cast<float>(number(*e, "ior", 1.5));
      float transmission = 0.0f;
      if (const auto* e = extension(gm.extensions, "KHR_materials_transmission"))
        transmission = static_cast<float>(number(*e, "transmissionFactor", 0.0));

      if (transmission >= 0.5f) {
        m.type = MaterialType::kDielectric;
        m.transmittance = base;  // glTF tints transmitted light by the base colour
        m.specular = Color(1.0f);
      } else if (metallic >= 0.5f) {
        m.type = MaterialType::kConductor;
        set_conductor_from_reflectance(m, base);
      } else if (m.roughness < 0.5f) {
        // A glossy dielectric: Blinn lobe with the glTF's 4 % specular reflectance and the
        // exponent matching Beckmann roughness α = roughness² (Walter et al. 2007:
        // n = 2/α² − 2), capped where it is a mirror for all practical purposes.
        m.type = MaterialType::kBlinn;
        m.specular = Color(0.04f);
        const float alpha = std::max(m.roughness * m.roughness, 1e-3f);
        m.exponent = std::min(2.0f / (alpha * alpha) - 2.0f, 1e4f);
      }
      scene_.materials.push_back(m);
    }
  }

  // Gulbrandsen 2014, "Artist Friendly Metallic Fresnel": the complex index whose normal
  // reflectance equals r, with the edge tint g = r (per channel, r clamped below 1).
  // n = g·(1−r)/(1+r) + (1−g)·(1+√r)/(1−√r), k = √((r(n+1)² − (n−1)²)/(1−r)).
  static void set_conductor_from_reflectance(Material& m, const Color& reflectance) {
    for (int c = 0; c < 3; ++c) {
      const float r = std::clamp(reflectance[c], 0.0f, 0.99f);
      const float g = r;
      const float sr = std::sqrt(r);
      const float n = g * (1.0f - r) / (1.0f + r) + (1.0f - g) * (1.0f + sr) / (1.0f - sr);
      const float k2 = (r * (n + 1.0f) * (n + 1.0f) - (n - 1.0f) * (n - 1.0f)) / (1.0f - r);
      m.eta[c] = n;
      m.k[c] = std::sqrt(std::max(k2, 0.0f));
    }
    m.specular = reflectance;
  }

  void read_meshes() {
    mesh_primitives_.resize(model_.meshes.size());
    for (size_t mi = 0; mi < model_.meshes.size(); ++mi) {
      const tinygltf::Mesh& gmesh = model_.meshes[mi];
      for (size_t pi = 0; pi < gmesh.primitives.size(); ++pi) {
        const tinygltf::Primitive& prim = gmesh.primitives[pi];
        const std::string name =
            gmesh.primitives.size() > 1 ? fmt::format("{}/{}", gmesh.name, pi) : gmesh.name;
        if (prim.mode != TINYGLTF_MODE_TRIANGLES) {
          add_warning(scene_, fmt::format("{}: mesh '{}' primitive {} has mode {} (only "
                                          "triangles are supported); skipped",
                                          path_, gmesh.name, pi, prim.mode));
          continue;
        }
        auto attr = [&](const char* key) {
          auto it = prim.attributes.find(key);
          return it == prim.attributes.end() ? -1 : it->second;
        };
        if (attr("POSITION") < 0)
          fail(fmt::format("mesh '{}' primitive {} has no POSITION attribute", gmesh.name, pi));
        Mesh mesh;
        mesh.name = name;
        const auto pos = read_floats(attr("POSITION"), 3, "POSITION");
        for (size_t i = 0; i + 2 < pos.size(); i += 3)
          mesh.positions.emplace_back(pos[i], pos[i + 1], pos[i + 2]);
        const size_t nv = mesh.positions.size();
        auto check_count = [&](const std::vector<float>& v, int comps, const char* what) {
          if (v.size() != nv * comps)
            fail(fmt::format("mesh '{}' primitive {}: {} has {} elements for {} positions",
                             gmesh.name, pi, what, v.size() / comps, nv));
        };
        if (attr("NORMAL") >= 0) {
          const auto n = read_floats(attr("NORMAL"), 3, "NORMAL");
          check_count(n, 3, "NORMAL");
          for (size_t i = 0; i < nv; ++i)
            mesh.normals.emplace_back(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
        }
        if (attr("TANGENT") >= 0) {
          const auto t = read_floats(attr("TANGENT"), 4, "TANGENT");
          check_count(t, 4, "TANGENT");
          for (size_t i = 0; i < nv; ++i)
            mesh.tangents.emplace_back(t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]);
        }
        if (attr("TEXCOORD_0") >= 0) {
          const auto t = read_floats(attr("TEXCOORD_0"), 2, "TEXCOORD_0");
          check_count(t, 2, "TEXCOORD_0");
          for (size_t i = 0; i < nv; ++i) mesh.uv0.emplace_back(t[2 * i], t[2 * i + 1]);
        }
        if (attr("TEXCOORD_1") >= 0) {
          const auto t = read_floats(attr("TEXCOORD_1"), 2, "TEXCOORD_1");
          check_count(t, 2, "TEXCOORD_1");
          for (size_t i = 0; i < nv; ++i) mesh.uv1.emplace_back(t[2 * i], t[2 * i + 1]);
        }
        if (prim.indices >= 0) {
          mesh.indices = read_indices(prim.indices);
        } else {
          mesh.indices.resize(nv - nv % 3);
          for (size_t i = 0; i < mesh.indices.size(); ++i)
            mesh.indices[i] = static_cast<uint32_t>(i);
        }
        if (prim.material >= 0 && static_cast<size_t>(prim.material) >= model_.materials.size())
          fail(fmt::format("mesh '{}' primitive {} refers to material {}, which does not exist",
                           gmesh.name, pi, prim.material));
        mesh.material = prim.material >= 0 ? prim.material : default_material();
        validate_mesh(mesh, path_, scene_.materials.size());
        mesh_primitives_[mi].push_back(static_cast<int>(scene_.meshes.size()));
        scene_.meshes.push_back(std::move(mesh));
      }
    }
  }

  int default_material() {
    if (default_material_ < 0) {
      default_material_ = static_cast<int>(scene_.materials.size());
      Material m;
      m.name = "default";
      m.albedo = Color(1.0f);  // glTF's default material: white, fully rough dielectric
      scene_.materials.push_back(m);
    }
    return default_material_;
  }

  static mat4 local_transform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
      mat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = static_cast<float>(node.matrix[4 * c + r]);
      return m;
    }
    mat4 m(1.0f);
    if (node.translation.size() == 3)
      m = glm::translate(m, vec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) {
      // glTF stores the quaternion as (x, y, z, w).
      const glm::quat q(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                        static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2]));
      m = m * glm::mat4_cast(q);
    }
    if (node.scale.size() == 3)
      m = glm::scale(m, vec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
  }

  void read_nodes() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 &&
                            static_cast<size_t>(model_.defaultScene) < model_.scenes.size()
                        ? model_.defaultScene
                        : 0;
      roots = model_.scenes[s].nodes;
    } else {
      // No scene: every node that is nobody's child is a root.
      std::vector<bool> is_child(model_.nodes.size(), false);
      for (const auto& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && static_cast<size_t>(c) < is_child.size()) is_child[c] = true;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(static_cast<int>(i));
    }
    std::vector<bool> visiting(model_.nodes.size(), false);
    for (int r : roots) visit(r, mat4(1.0f), visiting);
  }

  void visit(int index, const mat4& parent, std::vector<bool>& visiting) {
    if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
      fail(fmt::format("node {} does not exist", index));
    if (visiting[index]) fail(fmt::format("node {} is its own ancestor (cycle)", index));
    visiting[index] = true;
    const tinygltf::Node& node = model_.nodes[index];
    const mat4 world = parent * local_transform(node);
    if (node.mesh >= 0) {
      if (static_cast<size_t>(node.mesh) >= model_.meshes.size())
        fail(fmt::format("node {} refers to mesh {}, which does not exist", index, node.mesh));
      for (int m : mesh_primitives_[node.mesh]) {
        Instance inst;
        inst.name = node.name.empty() ? model_.meshes[node.mesh].name : node.name;
        inst.mesh = m;
        inst.transform = world;
        scene_.instances.push_back(inst);
      }
    }
    const vec3 origin = vec3(world * vec4(0, 0, 0, 1));
    const vec3 forward = glm::normalize(mat3(world) * vec3(0, 0, -1));
    if (node.camera >= 0 && !scene_.camera) {
      if (static_cast<size_t>(node.camera) >= model_.cameras.size())
        fail(fmt::format("node {} refers to camera {}, which does not exist", index, node.camera));
      const tinygltf::Camera& cam = model_.cameras[node.camera];
      if (cam.type == "perspective") {
        Camera c;
        c.position = origin;
        c.look_at = origin + forward;
        c.up = glm::normalize(mat3(world) * vec3(0, 1, 0));
        c.fov_y = static_cast<float>(cam.perspective.yfov);
        if (!(c.fov_y > 0.0f && c.fov_y < kPi))
          fail(fmt::format("cameras[{}] has yfov {} outside (0, π)", node.camera, c.fov_y));
        scene_.camera = c;
      }
    }
    if (const auto* e = extension(node.extensions, "KHR_lights_punctual")) {
      const int li = static_cast<int>(number(*e, "light", -1));
      if (li < 0 || static_cast<size_t>(li) >= model_.lights.size())
        fail(fmt::format("node {} refers to light {}, which does not exist", index, li));
      add_light(model_.lights[li], li, origin, forward);
    }
    for (int c : node.children) visit(c, world, visiting);
    visiting[index] = false;
  }

  // glTF intensities are photometric (cd for point/spot, lux for directional); illum reads
  // the numbers as radiometric: W/sr for point/spot, W/m² for directional. The spot's outer
  // cone angle is its hard edge (the inner angle's smooth falloff is not modelled).
  void add_light(const tinygltf::Light& gl, int index, const vec3& position, const vec3& forward) {
    Light light;
    light.name = gl.name.empty() ? fmt::format("light{}", index) : gl.name;
    Color color(1.0f);
    if (gl.color.size() == 3) color = Color(gl.color[0], gl.color[1], gl.color[2]);
    const float intensity = static_cast<float>(gl.intensity);
    if (intensity < 0.0f || !std::isfinite(intensity))
      fail(fmt::format("KHR_lights_punctual light {} has a negative or non-finite intensity",
                       index));
    light.position = position;
    light.direction = forward;
    light.range = static_cast<float>(gl.range);
    if (gl.type == "point") {
      light.type = LightType::kPoint;
      light.intensity = intensity * color;
    } else if (gl.type == "spot") {
      light.type = LightType::kSpot;
      light.intensity = intensity * color;
      light.cone_half_angle = static_cast<float>(gl.spot.outerConeAngle);
      if (!(light.cone_half_angle > 0.0f && light.cone_half_angle <= 0.5f * kPi))
        fail(fmt::format("KHR_lights_punctual light {} has outerConeAngle {} outside (0, π/2]",
                         index, light.cone_half_angle));
    } else if (gl.type == "directional") {
      light.type = LightType::kDirectional;
      light.irradiance = intensity * color;
    } else {
      add_warning(scene_, fmt::format("{}: light {} has unknown type '{}'; skipped", path_, index,
                                      gl.type));
      return;
    }
    scene_.lights.push_back(light);
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  Scene& scene_;
  const LoadOptions& options_;
  std::map<std::pair<int, bool>, int> textures_;
  // Encoded bytes of the images tinygltf read from data: URIs and files (keep_image_bytes).
  const std::map<int, std::vector<uint8_t>>& image_bytes_;
  std::vector<std::vector<int>> mesh_primitives_;  // glTF mesh → illum meshes
  int default_material_ = -1;
};

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

// tinygltf's image hook: instead of its own stb decoding (which allocates whatever size an
// image declares), keep the encoded bytes of data: URIs and external files for
// GltfReader::texture, which decodes them with illum's checked decoder. BufferView images
// are read from their buffer there, after their range is checked (tinygltf passes a pointer
// it has not checked, so it is not read here).
bool keep_image_bytes(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void* user) {
  if (image->bufferView >= 0 || bytes == nullptr || size <= 0) return true;
  auto& kept = *static_cast<std::map<int, std::vector<uint8_t>>*>(user);
  kept[index].assign(bytes, bytes + size);
  return true;
}

}  // namespace

Scene load_gltf(const std::string& path, const LoadOptions& options) {
  if (!file_exists(path)) throw Error(fmt::format("{}: cannot open file", path));
  const bool binary = lower_extension(path) == ".glb";
  if (!binary) precheck_gltf_json(path);

  tinygltf::TinyGLTF loader;
  std::map<int, std::vector<uint8_t>> image_bytes;
  if (options.load_textures)
    loader.SetImageLoader(keep_image_bytes, &image_bytes);
  else
    loader.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    const bool buffer = err.find("buffer") != std::string::npos &&
                        (err.find("not found") != std::string::npos ||
                         err.find("Failed to load") != std::string::npos);
    throw Error(fmt::format("{}: {}{}", path, buffer ? "missing buffer: " : "invalid glTF: ",
                            one_line(err.empty() ? warn : err)));
  }
  Scene scene;
  scene.source_path = path;
  // tinygltf's warnings, minus those about images: a missing image is reported once, per
  // material, by the texture reader (and not at all when textures are not wanted).
  size_t start = 0;
  while (start < warn.size()) {
    size_t end = warn.find('\n', start);
    if (end == std::string::npos) end = warn.size();
    const std::string line = warn.substr(start, end - start);
    start = end + 1;
    if (line.empty() || line.find("image") != std::string::npos ||
        line.rfind("File not found", 0) == 0 || line.rfind("File is empty", 0) == 0 ||
        line.rfind("File read error", 0) == 0)
      continue;
    add_warning(scene, fmt::format("{}: {}", path, line));
  }
  GltfReader(path, model, scene, options, image_bytes).read();
  if (scene.materials.empty()) {
    Material m;
    m.name = "default";
    scene.materials.push_back(m);
  }
  return scene;
}

}  // namespace illum::detail
