// glTF 2.0 (.gltf, .glb) through tinygltf. Node transforms become instances, primitives
// meshes, metallic-roughness materials map onto illum's material types (mapping below and in
// docs/scene-format.md), KHR_lights_punctual lights become point/spot/directional lights and
// the first perspective camera in the node tree becomes Scene::camera.
//
// Before tinygltf sees the file, gltf_structure.cpp checks its container, JSON and every
// size, offset and index against the bytes that exist. Here every number is range-checked
// after parsing, under its glTF name, with the shared rules of scene_validation.h; decoding
// is charged against a budget proportional to the input, and the node tree is walked without
// recursion, so no file can exhaust the stack or the memory.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <span>

#include <tiny_gltf.h>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "illum/core/color.h"
#include "illum/core/error.h"
#include "illum/scene/gltf_accessors.h"
#include "illum/scene/gltf_lightmap.h"
#include "illum/scene/gltf_structure.h"
#include "illum/scene/loaders.h"
#include "illum/scene/mesh_processing.h"
#include "illum/scene/scene_validation.h"

namespace illum::detail {

namespace {

// The largest image side the commands accept (README: images are limited to 16384 a side).
constexpr double kMaxGltfImageSide = 16384.0;

using nlohmann::json;

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  std::replace(s.begin(), s.end(), '\n', ';');
  return s;
}

std::string quoted(const std::string& name) {
  return name.empty() ? std::string() : fmt::format(" '{}'", name);
}

const json* json_child(const json* o, const char* key) {
  if (o == nullptr || !o->is_object()) return nullptr;
  const auto it = o->find(key);
  return it == o->end() ? nullptr : &*it;
}

const json* json_element(const json* a, size_t i) {
  return a != nullptr && a->is_array() && i < a->size() ? &(*a)[i] : nullptr;
}

class GltfReader {
 public:
  GltfReader(const std::string& path, const tinygltf::Model& model, const GltfStructure& source,
             Scene& scene, const LoadOptions& options,
             const std::map<int, std::vector<uint8_t>>& image_bytes)
      : path_(path),
        model_(model),
        doc_(source.json),
        scene_(scene),
        options_(options),
        accessors_(path, model, source.input_bytes),
        image_bytes_(image_bytes) {}

  void read() {
    check_cameras();
    check_lights();
    read_materials();
    read_lightmap();
    read_meshes();
    read_nodes();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(fmt::format("{}: {}", path_, what));
  }

  // "x.gltf: materials[2] 'Glass'": the prefix of the shared value checks' messages.
  std::string where(const char* list, size_t index, const std::string& name) const {
    return fmt::format("{}: {}[{}]{}", path_, list, index, quoted(name));
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
    Texture tex;
    if (decode_texture(gltf_texture, srgb, material, &tex)) {
      id = static_cast<int>(scene_.textures.size());
      scene_.textures.push_back(std::move(tex));
    }
    textures_[key] = id;
    return id;
  }

  // The image of textures[gltf_texture] (an index checked by the caller), decoded into
  // `tex`; false when it is missing or unreadable and missing_texture let the load go on.
  bool decode_texture(int gltf_texture, bool srgb, const std::string& material, Texture* tex) {
    const int source = model_.textures[gltf_texture].source;
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
        // gltf_structure.cpp has checked every image's bufferView against its buffer before
        // tinygltf ran (tinygltf itself hands bufferView images over unchecked).
        ILLUM_CHECK(static_cast<size_t>(img.bufferView) < model_.bufferViews.size(),
                    "images[{}]: bufferView {} passed the structure check", source, img.bufferView);
        const tinygltf::BufferView& view = model_.bufferViews[img.bufferView];
        ILLUM_CHECK(
            view.buffer >= 0 && static_cast<size_t>(view.buffer) < model_.buffers.size() &&
                view.byteOffset <= model_.buffers[view.buffer].data.size() &&
                view.byteLength <= model_.buffers[view.buffer].data.size() - view.byteOffset,
            "images[{}]: bufferView {} outside its buffer passed the structure check", source,
            img.bufferView);
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
          tex->path = name;
          tex->srgb = srgb;
          tex->image = decode_image(bytes, name, srgb);  // an empty file is an error there
          return true;
        } catch (const Error& e) {
          missing_texture(
              scene_, options_,
              fmt::format("{}: texture of material '{}': {}", path_, material, e.what()));
        }
      }
    }
    return false;
  }

  // The light-map of illum's export (gltf_lightmap.h), decoded to linear RGB. Not a material
  // texture: Scene::textures are 8-bit colour on the GPU, which would clip its range.
  void read_lightmap() {
    std::optional<GltfLightmapReference> ref = find_gltf_lightmap(doc_, path_, scene_);
    if (!ref || static_cast<size_t>(ref->texture) >= model_.textures.size()) return;
    if (options_.load_textures) {
      Texture tex;
      if (!decode_texture(ref->texture, /*srgb=*/false, "(its light-map)", &tex)) return;
      ref->lightmap.image = decode_rgbm_lightmap(tex.image, ref->lightmap.range, tex.path);
    }
    scene_.lightmap = std::move(ref->lightmap);
  }

  void read_materials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& gm = model_.materials[i];
      const std::string at = where("materials", i, gm.name);
      Material m;
      m.name = gm.name;
      const auto& pbr = gm.pbrMetallicRoughness;
      const std::vector<double> base_factor = pbr.baseColorFactor;
      if (base_factor.size() != 4)
        throw Error(
            fmt::format("{} baseColorFactor has {} numbers, not 4", at, base_factor.size()));
      const Color base = factor_color(base_factor, at + " baseColorFactor");
      m.opacity = factor(base_factor[3], at + " baseColorFactor alpha");
      m.albedo = base;
      m.albedo_texture = texture(pbr.baseColorTexture.index, true, m.name);
      const float metallic = factor(pbr.metallicFactor, at + " metallicFactor");
      m.roughness = factor(pbr.roughnessFactor, at + " roughnessFactor");
      m.roughness_texture = texture(pbr.metallicRoughnessTexture.index, false, m.name);
      m.normal_texture = texture(gm.normalTexture.index, false, m.name);
      m.normal_scale = checked_float(gm.normalTexture.scale, at + " normalTexture.scale");
      if (gm.emissiveFactor.size() != 3)
        throw Error(
            fmt::format("{} emissiveFactor has {} numbers, not 3", at, gm.emissiveFactor.size()));
      m.emission = factor_color(gm.emissiveFactor, at + " emissiveFactor");
      m.emission_texture = texture(gm.emissiveTexture.index, true, m.name);
      m.emission *= checked_non_negative(
          extension_number(i, "KHR_materials_emissive_strength", "emissiveStrength", 1.0, at),
          at + " KHR_materials_emissive_strength.emissiveStrength");
      check_color(m.emission, at + " emission (emissiveFactor × emissiveStrength)");
      const double ior = extension_number(i, "KHR_materials_ior", "ior", 1.5, at);
      check_in_range(ior, 1.0, kMaxIor, at + " KHR_materials_ior.ior");
      m.ior = static_cast<float>(ior);
      const float transmission =
          factor(extension_number(i, "KHR_materials_transmission", "transmissionFactor", 0.0, at),
                 at + " KHR_materials_transmission.transmissionFactor");

      if (transmission >= 0.5f) {
        m.type = MaterialType::kDielectric;
        m.transmittance = base;  // glTF tints transmitted light by the base colour
        m.specular = Color(1.0f);
      } else if (metallic >= 0.5f) {
        m.type = MaterialType::kConductor;
        set_conductor_from_reflectance(m, base);
      }
      // glTF's roughness is perceptual; the GGX α of its BRDF is its square (glTF 2.0 spec,
      // appendix B). Only the factor: the offline microfacet lobes take one α per material.
      if (m.type == MaterialType::kDielectric || m.type == MaterialType::kConductor) {
        m.alpha = m.roughness * m.roughness;
      } else if (m.roughness < 0.5f) {
        // A glossy dielectric: Blinn lobe with the glTF's 4 % specular reflectance and the
        // exponent matching Beckmann roughness α = roughness² (Walter et al. 2007:
        // n = 2/α² − 2), capped where it is a mirror for all practical purposes.
        m.type = MaterialType::kBlinn;
        m.specular = Color(0.04f);
        const float alpha = std::max(m.roughness * m.roughness, 1e-3f);
        m.exponent = std::min(2.0f / (alpha * alpha) - 2.0f, 1e4f);
      }
      validate_material(m, at, scene_.textures.size());
      scene_.materials.push_back(m);
    }
  }

  // A glTF factor: a number in [0, 1].
  static float factor(double v, const std::string& what) {
    check_in_range(v, 0.0, 1.0, what);
    return static_cast<float>(v);
  }
  static Color factor_color(const std::vector<double>& v, const std::string& what) {
    return Color(factor(v[0], what), factor(v[1], what), factor(v[2], what));
  }

  // A number inside extension `name` of materials[i], read from our own parse of the JSON
  // (tinygltf keeps extension numbers as int or double values and truncates large integers).
  double extension_number(size_t material, const char* name, const char* key, double fallback,
                          const std::string& at) const {
    const json* value = json_child(
        json_child(json_child(json_element(json_child(&doc_, "materials"), material), "extensions"),
                   name),
        key);
    if (value == nullptr) return fallback;
    if (!value->is_number()) throw Error(fmt::format("{} {}.{} must be a number", at, name, key));
    return value->get<double>();
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
        const std::string at = fmt::format("meshes[{}]{} primitive {}", mi, quoted(gmesh.name), pi);
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
        if (attr("POSITION") < 0) fail(fmt::format("{} has no POSITION attribute", at));
        const size_t count = accessors_.accessor(attr("POSITION"), at + " POSITION").count;
        for (const char* key : {"NORMAL", "TANGENT", "TEXCOORD_0", "TEXCOORD_1"}) {
          if (attr(key) >= 0 && accessors_.accessor(attr(key), at + " " + key).count != count)
            fail(fmt::format("{}: {} has {} elements for {} positions", at, key,
                             accessors_.accessor(attr(key), at).count, count));
        }

        Mesh mesh;
        mesh.name = gmesh.primitives.size() > 1 ? fmt::format("{}/{}", gmesh.name, pi) : gmesh.name;
        // With indices, only the vertices they use are decoded, renumbered in their original
        // order: primitives that share one large vertex accessor (one per material is a common
        // export) then cost what they use, not the whole accessor each.
        std::vector<uint32_t> used;
        bool compact = false;
        if (prim.indices >= 0) {
          mesh.indices = accessors_.read_indices(prim.indices, count, at + " indices");
          used = mesh.indices;
          std::sort(used.begin(), used.end());
          used.erase(std::unique(used.begin(), used.end()), used.end());
          compact = used.size() < count;
          if (compact) {
            for (uint32_t& i : mesh.indices)
              i = static_cast<uint32_t>(std::lower_bound(used.begin(), used.end(), i) -
                                        used.begin());
          }
        } else {
          accessors_.charge(count, sizeof(uint32_t), at + " indices");
          mesh.indices.resize(count - count % 3);
          for (size_t i = 0; i < mesh.indices.size(); ++i)
            mesh.indices[i] = static_cast<uint32_t>(i);
        }
        const std::vector<uint32_t>* subset = compact ? &used : nullptr;
        std::vector<float> values;
        accessors_.read_attribute(attr("POSITION"), 3, at + " POSITION", subset, values);
        mesh.positions = to_vectors<vec3>(values);
        if (attr("NORMAL") >= 0) {
          accessors_.read_attribute(attr("NORMAL"), 3, at + " NORMAL", subset, values);
          mesh.normals = to_vectors<vec3>(values);
        }
        if (attr("TANGENT") >= 0) {
          accessors_.read_attribute(attr("TANGENT"), 4, at + " TANGENT", subset, values);
          mesh.tangents = to_vectors<vec4>(values);
        }
        if (attr("TEXCOORD_0") >= 0) {
          accessors_.read_attribute(attr("TEXCOORD_0"), 2, at + " TEXCOORD_0", subset, values);
          mesh.uv0 = to_vectors<vec2>(values);
        }
        if (attr("TEXCOORD_1") >= 0) {
          accessors_.read_attribute(attr("TEXCOORD_1"), 2, at + " TEXCOORD_1", subset, values);
          mesh.uv1 = to_vectors<vec2>(values);
        }
        if (prim.material >= 0 && static_cast<size_t>(prim.material) >= model_.materials.size())
          fail(fmt::format("{} refers to material {}, which does not exist", at, prim.material));
        mesh.material = prim.material >= 0 ? prim.material : default_material();
        validate_mesh(mesh, path_, scene_.materials.size());
        mesh_primitives_[mi].push_back(static_cast<int>(scene_.meshes.size()));
        scene_.meshes.push_back(std::move(mesh));
      }
    }
  }

  template <typename V>
  static std::vector<V> to_vectors(const std::vector<float>& values) {
    constexpr size_t n = V::length();
    std::vector<V> out(values.size() / n);
    std::memcpy(out.data(), values.data(), out.size() * sizeof(V));
    return out;
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

  // The node's local transform: `matrix`, or T·R·S. Every number must be a finite float; a
  // rotation is normalized (writers round it), but a zero quaternion is an error.
  mat4 local_transform(const tinygltf::Node& node, const std::string& at) const {
    auto numbers = [&](const std::vector<double>& v, size_t n, const char* name) {
      if (v.size() != n)
        throw Error(fmt::format("{} {} has {} numbers, not {}", at, name, v.size(), n));
      std::vector<float> out(n);
      for (size_t i = 0; i < n; ++i) out[i] = checked_float(v[i], fmt::format("{} {}", at, name));
      return out;
    };
    const bool trs = !node.translation.empty() || !node.rotation.empty() || !node.scale.empty();
    if (!node.matrix.empty()) {
      if (trs) throw Error(fmt::format("{} has both a matrix and translation/rotation/scale", at));
      const auto v = numbers(node.matrix, 16, "matrix");
      mat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = v[4 * c + r];
      return m;
    }
    mat4 m(1.0f);
    if (!node.translation.empty()) {
      const auto t = numbers(node.translation, 3, "translation");
      m = glm::translate(m, vec3(t[0], t[1], t[2]));
    }
    if (!node.rotation.empty()) {
      // glTF stores the quaternion as (x, y, z, w).
      const auto q = numbers(node.rotation, 4, "rotation");
      const glm::quat rotation(q[3], q[0], q[1], q[2]);
      const float length = glm::length(rotation);
      if (!(length > 0.0f) || !std::isfinite(length))
        throw Error(fmt::format("{} rotation is not a usable quaternion", at));
      m = m * glm::mat4_cast(rotation / length);
    }
    if (!node.scale.empty()) {
      const auto s = numbers(node.scale, 3, "scale");
      m = glm::scale(m, vec3(s[0], s[1], s[2]));
    }
    return m;
  }

  // Walks the default scene's trees (or every root when there is no scene) depth-first with
  // an explicit stack, so a chain of a million nodes costs heap, not stack. glTF node
  // hierarchies are disjoint trees: a node met twice (a cycle, two parents, or listed twice
  // as a root) is an error, which also keeps a small file from expanding exponentially.
  void read_nodes() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      if (model_.defaultScene >= 0 &&
          static_cast<size_t>(model_.defaultScene) >= model_.scenes.size())
        fail(fmt::format("scene = {}, but the file has {} scenes", model_.defaultScene,
                         model_.scenes.size()));
      roots = model_.scenes[std::max(model_.defaultScene, 0)].nodes;
    } else {
      // No scene: every node that is nobody's child is a root.
      std::vector<bool> is_child(model_.nodes.size(), false);
      for (const auto& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && static_cast<size_t>(c) < is_child.size()) is_child[c] = true;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(static_cast<int>(i));
    }
    enum : uint8_t { kUnseen, kOnPath, kDone };
    std::vector<uint8_t> state(model_.nodes.size(), kUnseen);
    struct Frame {
      int node;
      mat4 world;
      size_t next_child;
    };
    std::vector<Frame> stack;
    auto enter = [&](int index, const mat4& parent, const char* via) {
      if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
        fail(fmt::format("{} node {} does not exist", via, index));
      if (state[index] == kOnPath) fail(fmt::format("node {} is its own ancestor (cycle)", index));
      if (state[index] == kDone)
        fail(
            fmt::format("node {} is reached twice (two parents, or listed twice); glTF node "
                        "hierarchies must be disjoint trees",
                        index));
      state[index] = kOnPath;
      const tinygltf::Node& node = model_.nodes[index];
      const mat4 world = parent * local_transform(node, where("nodes", index, node.name));
      visit(index, world);
      stack.push_back({index, world, 0});
    };
    for (int r : roots) {
      enter(r, mat4(1.0f), "the scene's root");
      while (!stack.empty()) {
        Frame& top = stack.back();
        const std::vector<int>& children = model_.nodes[top.node].children;
        if (top.next_child < children.size()) {
          const int child = children[top.next_child++];
          const mat4 world = top.world;  // `top` dangles once enter() grows the stack
          enter(child, world, "a child");
        } else {
          state[top.node] = kDone;
          stack.pop_back();
        }
      }
    }
  }

  // What one node adds: an instance per primitive of its mesh, the camera, a light.
  void visit(int index, const mat4& world) {
    const tinygltf::Node& node = model_.nodes[index];
    const std::string at = where("nodes", index, node.name);
    const bool has_light = node.extensions.count("KHR_lights_punctual") > 0;
    if (node.mesh >= 0 || node.camera >= 0 || has_light) check_transform(world, at);
    if (node.mesh >= 0) {
      if (static_cast<size_t>(node.mesh) >= model_.meshes.size())
        fail(fmt::format("node {} refers to mesh {}, which does not exist", index, node.mesh));
      for (int m : mesh_primitives_[node.mesh]) {
        Instance inst;
        inst.name = node.name.empty() ? model_.meshes[node.mesh].name : node.name;
        inst.mesh = m;
        inst.transform = world;
        accessors_.charge(1, sizeof(Instance) + inst.name.size(), at + " instances");
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
        validate_camera(c, at + " camera");
        scene_.camera = c;
        // The camera's aspectRatio (checked positive when given) sets the image's shape:
        // the default height stays, the width follows. Command-line sizes still win.
        if (cam.perspective.aspectRatio > 0.0) {
          const double width = std::round(scene_.settings.height * cam.perspective.aspectRatio);
          if (!(width <= kMaxGltfImageSide))
            fail(fmt::format(
                "{} camera aspectRatio = {} makes a {} × {} image, wider than {} "
                "pixels",
                at, cam.perspective.aspectRatio, width, scene_.settings.height, kMaxGltfImageSide));
          scene_.settings.width = std::max(1, static_cast<int>(width));
        }
      }
    }
    if (has_light) {
      const json* light = json_child(
          json_child(json_child(json_element(json_child(&doc_, "nodes"), index), "extensions"),
                     "KHR_lights_punctual"),
          "light");
      const int li = light != nullptr && light->is_number_unsigned() ? light->get<int>() : -1;
      if (li < 0 || static_cast<size_t>(li) >= model_.lights.size())
        fail(fmt::format("node {} refers to light {}, which does not exist", index, li));
      add_light(model_.lights[li], li, origin, forward);
    }
  }

  // Every camera in the list, used or not, against glTF's rules: perspective yfov in (0, π),
  // znear > 0, zfar (when given) > znear, aspectRatio (when given) > 0; orthographic xmag and
  // ymag non-zero, znear ≥ 0, zfar > znear.
  void check_cameras() const {
    const json* list = json_child(&doc_, "cameras");
    for (size_t i = 0; i < model_.cameras.size(); ++i) {
      const tinygltf::Camera& cam = model_.cameras[i];
      const std::string at = where("cameras", i, cam.name);
      const json* raw = json_child(json_element(list, i), cam.type.c_str());
      if (cam.type == "perspective") {
        const auto& p = cam.perspective;
        const float yfov = checked_float(p.yfov, at + " yfov");
        if (!(yfov > 0.0f && yfov < kPi))
          throw Error(fmt::format("{} yfov = {} is outside (0, π)", at, yfov));
        if (!(checked_float(p.znear, at + " znear") > 0.0f))
          throw Error(fmt::format("{} znear = {} must be positive", at, p.znear));
        if (json_child(raw, "zfar") != nullptr && !(checked_float(p.zfar, at + " zfar") > p.znear))
          throw Error(fmt::format("{} zfar = {} must exceed znear = {}", at, p.zfar, p.znear));
        if (json_child(raw, "aspectRatio") != nullptr &&
            !(checked_float(p.aspectRatio, at + " aspectRatio") > 0.0f))
          throw Error(fmt::format("{} aspectRatio = {} must be positive", at, p.aspectRatio));
      } else if (cam.type == "orthographic") {
        const auto& o = cam.orthographic;
        if (checked_float(o.xmag, at + " xmag") == 0.0f ||
            checked_float(o.ymag, at + " ymag") == 0.0f)
          throw Error(fmt::format("{} xmag and ymag must not be zero", at));
        if (!(checked_float(o.znear, at + " znear") >= 0.0f) ||
            !(checked_float(o.zfar, at + " zfar") > o.znear))
          throw Error(fmt::format("{} needs 0 ≤ znear < zfar (znear = {}, zfar = {})", at, o.znear,
                                  o.zfar));
      } else {
        throw Error(
            fmt::format("{} type '{}' is neither perspective nor orthographic", at, cam.type));
      }
    }
  }

  // Every KHR_lights_punctual light against the extension's rules: a known type, colour
  // components in [0, 1], intensity ≥ 0, range (when given) > 0, spot cone angles
  // 0 ≤ inner ≤ outer ≤ π/2 with outer > 0.
  void check_lights() const {
    const json* list =
        json_child(json_child(json_child(&doc_, "extensions"), "KHR_lights_punctual"), "lights");
    for (size_t i = 0; i < model_.lights.size(); ++i) {
      const tinygltf::Light& gl = model_.lights[i];
      const std::string at = where("KHR_lights_punctual lights", i, gl.name);
      if (gl.type != "point" && gl.type != "spot" && gl.type != "directional")
        throw Error(fmt::format("{} type '{}' is not point, spot or directional", at, gl.type));
      if (!gl.color.empty()) {
        if (gl.color.size() != 3)
          throw Error(fmt::format("{} color has {} numbers, not 3", at, gl.color.size()));
        factor_color(gl.color, at + " color");
      }
      checked_non_negative(gl.intensity, at + " intensity");
      if (json_child(json_element(list, i), "range") != nullptr &&
          !(checked_float(gl.range, at + " range") > 0.0f))
        throw Error(fmt::format("{} range = {} must be positive", at, gl.range));
      if (gl.type == "spot") {
        const float inner = checked_float(gl.spot.innerConeAngle, at + " spot.innerConeAngle");
        const float outer = checked_float(gl.spot.outerConeAngle, at + " spot.outerConeAngle");
        if (!(outer > 0.0f && outer <= 0.5f * kPi))
          throw Error(fmt::format("{} spot.outerConeAngle = {} is outside (0, π/2]", at, outer));
        if (!(inner >= 0.0f && inner <= outer))
          throw Error(
              fmt::format("{} spot.innerConeAngle = {} is outside [0, outerConeAngle]", at, inner));
      }
    }
  }

  // glTF intensities are photometric (cd for point/spot, lux for directional); illum's
  // lights are radiometric (W/sr, W/m²): divided by the luminous efficacy of 683 lm/W, as
  // Blender's importer does (kLuminousEfficacy). The spot's outer cone angle is its hard
  // edge (the inner angle's smooth falloff is not modelled). The values were checked by
  // check_lights.
  void add_light(const tinygltf::Light& gl, int index, const vec3& position, const vec3& forward) {
    Light light;
    light.name = gl.name.empty() ? fmt::format("light{}", index) : gl.name;
    Color color(1.0f);
    if (gl.color.size() == 3) color = Color(gl.color[0], gl.color[1], gl.color[2]);
    const float intensity = static_cast<float>(gl.intensity / kLuminousEfficacy);
    // illum's export marks the lights its light-map already holds.
    const json* baked =
        json_child(json_child(json_element(json_child(json_child(json_child(&doc_, "extensions"),
                                                                 "KHR_lights_punctual"),
                                                      "lights"),
                                           static_cast<size_t>(index)),
                              "extras"),
                   "illum_baked");
    light.in_lightmap = baked != nullptr && baked->is_boolean() && baked->get<bool>();
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
    } else {
      light.type = LightType::kDirectional;
      light.irradiance = intensity * color;
    }
    validate_light(light, where("KHR_lights_punctual lights", index, gl.name),
                   scene_.instances.size(), false);
    scene_.lights.push_back(light);
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  const json& doc_;
  Scene& scene_;
  const LoadOptions& options_;
  GltfAccessors accessors_;
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
  const GltfStructure structure = check_gltf_structure(path);

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
  // tinygltf reports some spec violations in `err` and still returns true (a malformed
  // baseColorFactor is dropped for the default): those are errors here too.
  if (!ok || !err.empty()) {
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
  GltfReader(path, model, structure, scene, options, image_bytes).read();
  if (scene.materials.empty()) {
    Material m;
    m.name = "default";
    scene.materials.push_back(m);
  }
  return scene;
}

}  // namespace illum::detail
