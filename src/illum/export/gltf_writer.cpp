#include "illum/export/gltf_writer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include <stb_image_write.h>
#include <tiny_gltf.h>

#include "illum/core/color.h"
#include "illum/core/error.h"

namespace illum::exporter {

namespace {

constexpr int kArrayBuffer = 34962;         // GL_ARRAY_BUFFER
constexpr int kElementArrayBuffer = 34963;  // GL_ELEMENT_ARRAY_BUFFER
constexpr int kLinear = 9729;               // GL_LINEAR
constexpr int kClampToEdge = 33071;         // GL_CLAMP_TO_EDGE

using tinygltf::Value;

void append_png(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* bytes = static_cast<const uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

uint8_t to_byte(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

float clamp01(float v) {
  return std::clamp(v, 0.0f, 1.0f);
}

// Builds the tinygltf model: one buffer holding every view, 4-byte aligned.
class ModelBuilder {
 public:
  ModelBuilder(const Scene& scene, const GltfLightmapTexture* lightmap, GltfWriteSummary& summary)
      : scene_(scene), lightmap_(lightmap), summary_(summary) {
    model_.asset.version = "2.0";
    model_.asset.generator = "illum export";
    model_.buffers.emplace_back();
  }

  tinygltf::Model build() {
    textures();
    const int lightmap_texture = lightmap_ != nullptr ? add_lightmap_texture() : -1;
    materials(lightmap_texture);
    meshes();
    tinygltf::Scene root;
    for (size_t i = 0; i < scene_.instances.size(); ++i) root.nodes.push_back(instance_node(i));
    if (scene_.camera) root.nodes.push_back(camera_node(*scene_.camera));
    lights(root);
    model_.scenes.push_back(root);
    model_.defaultScene = 0;
    for (const std::string& used : used_) model_.extensionsUsed.push_back(used);
    summary_.meshes = model_.meshes.size();
    summary_.nodes = model_.nodes.size();
    summary_.materials = model_.materials.size();
    summary_.textures = model_.textures.size();
    return std::move(model_);
  }

 private:
  void use(const std::string& extension) {
    if (std::find(used_.begin(), used_.end(), extension) == used_.end()) used_.push_back(extension);
  }

  int add_view(const void* data, size_t bytes, int target) {
    std::vector<unsigned char>& bin = model_.buffers[0].data;
    while (bin.size() % 4 != 0) bin.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bin.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + bytes);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  template <typename V>
  int add_float_accessor(const std::vector<V>& values, int type, bool with_bounds) {
    constexpr int n = V::length();
    tinygltf::Accessor acc;
    acc.bufferView = add_view(values.data(), values.size() * sizeof(V), kArrayBuffer);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = values.size();
    acc.type = type;
    if (with_bounds) {  // glTF requires min/max on POSITION
      acc.minValues.assign(n, std::numeric_limits<double>::infinity());
      acc.maxValues.assign(n, -std::numeric_limits<double>::infinity());
      for (const V& v : values)
        for (int c = 0; c < n; ++c) {
          acc.minValues[c] = std::min<double>(acc.minValues[c], v[c]);
          acc.maxValues[c] = std::max<double>(acc.maxValues[c], v[c]);
        }
    }
    model_.accessors.push_back(acc);
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  int add_image(const std::vector<uint8_t>& png, const std::string& name) {
    tinygltf::Image image;
    image.name = name;
    image.mimeType = "image/png";
    image.bufferView = add_view(png.data(), png.size(), 0);
    model_.bufferViews.back().target = 0;  // images are not vertex data
    model_.images.push_back(image);
    return static_cast<int>(model_.images.size()) - 1;
  }

  // Every scene texture as a PNG (glTF core has PNG and JPEG; PNG keeps the 8 bits exact).
  void textures() {
    for (size_t i = 0; i < scene_.textures.size(); ++i) {
      const Texture& texture = scene_.textures[i];
      const Image& image = texture.image;
      std::vector<uint8_t> bytes(image.data().size());
      const int channels = image.channels();
      for (size_t k = 0; k < bytes.size(); ++k) {
        const int c = static_cast<int>(k % static_cast<size_t>(channels));
        const float v = image.data()[k];
        bytes[k] = to_byte(texture.srgb && !is_alpha_channel(c, channels) ? srgb_encode(v) : v);
      }
      tinygltf::Texture t;
      t.source = add_image(encode_png(bytes, image.width(), image.height(), channels),
                           fmt::format("texture{}", i));
      model_.textures.push_back(t);
    }
  }

  int add_lightmap_texture() {
    tinygltf::Sampler sampler;  // no mipmaps: they would blend texels of different charts
    sampler.magFilter = kLinear;
    sampler.minFilter = kLinear;
    sampler.wrapS = kClampToEdge;
    sampler.wrapT = kClampToEdge;
    model_.samplers.push_back(sampler);
    tinygltf::Texture t;
    t.name = "illum light-map (" + lightmap_->encoding + ")";
    t.sampler = static_cast<int>(model_.samplers.size()) - 1;
    t.source = add_image(lightmap_->png, "lightmap");
    model_.textures.push_back(t);
    return static_cast<int>(model_.textures.size()) - 1;
  }

  void materials(int lightmap_texture) {
    bool phong = false, conductor = false;
    for (const Material& m : scene_.materials) {
      tinygltf::Material g;
      g.name = m.name;
      auto& pbr = g.pbrMetallicRoughness;
      Color base = m.albedo;
      pbr.metallicFactor = 0.0;
      pbr.roughnessFactor = clamp01(m.roughness);
      switch (m.type) {
        case MaterialType::kLambert:
          break;
        case MaterialType::kPhong:
        case MaterialType::kBlinn:
          phong = true;
          break;
        case MaterialType::kMirror:
        case MaterialType::kConductor:
          conductor = conductor || m.type == MaterialType::kConductor;
          base = m.specular;
          pbr.metallicFactor = 1.0;
          pbr.roughnessFactor = std::sqrt(m.type == MaterialType::kConductor ? m.alpha : 0.0f);
          break;
        case MaterialType::kDielectric: {
          base = m.transmittance;
          pbr.roughnessFactor = std::sqrt(m.alpha);  // glTF roughness² = GGX α
          tinygltf::Value::Object transmission{{"transmissionFactor", Value(1.0)}};
          g.extensions["KHR_materials_transmission"] = Value(transmission);
          tinygltf::Value::Object ior{{"ior", Value(static_cast<double>(m.ior))}};
          g.extensions["KHR_materials_ior"] = Value(ior);
          use("KHR_materials_transmission");
          use("KHR_materials_ior");
          break;
        }
      }
      pbr.baseColorFactor = {clamp01(base.r), clamp01(base.g), clamp01(base.b), clamp01(m.opacity)};
      if (m.albedo_texture != kNoTexture) pbr.baseColorTexture.index = m.albedo_texture;
      if (m.roughness_texture != kNoTexture)
        pbr.metallicRoughnessTexture.index = m.roughness_texture;
      if (m.normal_texture != kNoTexture) {
        g.normalTexture.index = m.normal_texture;
        g.normalTexture.scale = m.normal_scale;
      }
      if (m.emission_texture != kNoTexture) g.emissiveTexture.index = m.emission_texture;
      const float strength = max_component(m.emission);
      if (strength > 1.0f) {
        const Color factor = m.emission / strength;
        g.emissiveFactor = {factor.r, factor.g, factor.b};
        tinygltf::Value::Object s{{"emissiveStrength", Value(static_cast<double>(strength))}};
        g.extensions["KHR_materials_emissive_strength"] = Value(s);
        use("KHR_materials_emissive_strength");
      } else {
        g.emissiveFactor = {m.emission.r, m.emission.g, m.emission.b};
      }
      if (lightmap_texture >= 0) {
        tinygltf::Value::Object info{{"index", Value(lightmap_texture)}, {"texCoord", Value(1)}};
        tinygltf::Value::Object extras{{"encoding", Value(lightmap_->encoding)},
                                       {"range", Value(static_cast<double>(lightmap_->range))},
                                       {"tone", Value(lightmap_->tone)},
                                       {"basis", Value(lightmap_->basis)},
                                       {"layer", Value(lightmap_->layer)},
                                       {"bytes", Value(std::string("linear"))}};
        tinygltf::Value::Object ext{{"lightmapTexture", Value(info)}, {"extras", Value(extras)}};
        g.extensions["MSFT_lightmap"] = Value(ext);
        use("MSFT_lightmap");
      }
      model_.materials.push_back(g);
    }
    if (phong)
      summary_.dropped.push_back(
          "Phong/Blinn exponents and specular colours (glTF has roughness only)");
    if (conductor)
      summary_.dropped.push_back(
          "conductor complex indices (the base colour is the normal-incidence reflectance)");
  }

  void meshes() {
    for (const Mesh& mesh : scene_.meshes) {
      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.material = mesh.material;
      prim.attributes["POSITION"] =
          add_float_accessor(mesh.positions, TINYGLTF_TYPE_VEC3, /*with_bounds=*/true);
      if (mesh.normals.size() == mesh.positions.size())
        prim.attributes["NORMAL"] = add_float_accessor(mesh.normals, TINYGLTF_TYPE_VEC3, false);
      if (!mesh.tangents.empty() && mesh.tangents.size() == mesh.positions.size())
        prim.attributes["TANGENT"] = add_float_accessor(mesh.tangents, TINYGLTF_TYPE_VEC4, false);
      if (!mesh.uv0.empty() && mesh.uv0.size() == mesh.positions.size())
        prim.attributes["TEXCOORD_0"] = add_float_accessor(mesh.uv0, TINYGLTF_TYPE_VEC2, false);
      if (!mesh.uv1.empty() && mesh.uv1.size() == mesh.positions.size())
        prim.attributes["TEXCOORD_1"] = add_float_accessor(mesh.uv1, TINYGLTF_TYPE_VEC2, false);
      tinygltf::Accessor indices;
      indices.bufferView = add_view(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t),
                                    kElementArrayBuffer);
      indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      indices.count = mesh.indices.size();
      indices.type = TINYGLTF_TYPE_SCALAR;
      model_.accessors.push_back(indices);
      prim.indices = static_cast<int>(model_.accessors.size()) - 1;
      tinygltf::Mesh g;
      g.name = mesh.name;
      g.primitives.push_back(prim);
      model_.meshes.push_back(g);
    }
  }

  static std::vector<double> matrix(const mat4& m) {
    std::vector<double> out(16);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) out[4 * c + r] = m[c][r];  // glTF: column-major, as glm
    return out;
  }

  int add_node(tinygltf::Node node) {
    model_.nodes.push_back(std::move(node));
    return static_cast<int>(model_.nodes.size()) - 1;
  }

  int instance_node(size_t i) {
    const Instance& instance = scene_.instances[i];
    tinygltf::Node node;
    node.name = instance.name;
    node.mesh = instance.mesh;
    if (instance.transform != mat4(1.0f)) node.matrix = matrix(instance.transform);
    return add_node(node);
  }

  int camera_node(const Camera& camera) {
    tinygltf::Camera c;
    c.type = "perspective";
    c.perspective.yfov = camera.fov_y;
    c.perspective.aspectRatio =
        static_cast<double>(scene_.settings.width) / std::max(scene_.settings.height, 1);
    const Bounds3 bounds = scene_.bounds();
    const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.max - bounds.min);
    c.perspective.znear = 1e-3 * std::max(diagonal, 1e-3f);
    // tinygltf always writes zfar (glTF: absent = infinite), so a finite one far past the scene.
    c.perspective.zfar = 1e3 * std::max(diagonal, 1e-3f);
    model_.cameras.push_back(c);
    tinygltf::Node node;
    node.name = "camera";
    node.camera = static_cast<int>(model_.cameras.size()) - 1;
    node.matrix = matrix(glm::inverse(camera.view_matrix()));  // camera → world, looks down −z
    summary_.camera = true;
    return add_node(node);
  }

  // A rotation taking the node's −z (glTF's light direction) onto `direction`.
  static mat4 facing(const vec3& position, const vec3& direction) {
    const vec3 back = -glm::normalize(direction);
    const vec3 helper = std::abs(back.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
    const vec3 right = glm::normalize(glm::cross(helper, back));
    const vec3 up = glm::cross(back, right);
    mat4 m(1.0f);
    m[0] = vec4(right, 0.0f);
    m[1] = vec4(up, 0.0f);
    m[2] = vec4(back, 0.0f);
    m[3] = vec4(position, 1.0f);
    return m;
  }

  void lights(tinygltf::Scene& root) {
    size_t area = 0;
    for (size_t i = 0; i < scene_.lights.size(); ++i) {
      const Light& light = scene_.lights[i];
      if (light.type == LightType::kArea || light.type == LightType::kEnvironment) {
        area += light.type == LightType::kArea;
        continue;
      }
      tinygltf::Light g;
      g.name = light.name;
      const Color value =
          light.type == LightType::kDirectional ? light.irradiance : light.intensity;
      const float largest = max_component(value);
      const Color color = largest > 0.0f ? value / largest : Color(1.0f);
      g.color = {color.r, color.g, color.b};
      // Photometric, as glTF defines it (cd, lux): the loader's inverse (kLuminousEfficacy).
      g.intensity = largest * kLuminousEfficacy;
      if (light.range > 0.0f) g.range = light.range;
      if (light.type == LightType::kPoint) {
        g.type = "point";
      } else if (light.type == LightType::kSpot) {
        g.type = "spot";
        g.spot.outerConeAngle = light.cone_half_angle;
        g.spot.innerConeAngle = std::nextafter(light.cone_half_angle, 0.0f);
      } else {
        g.type = "directional";
      }
      if (lightmap_ != nullptr && i < lightmap_->light_baked.size())
        g.extras =
            Value(tinygltf::Value::Object{{"illum_baked", Value(lightmap_->light_baked[i])}});
      model_.lights.push_back(g);
      tinygltf::Node node;
      node.name = light.name;
      const mat4 m = light.type == LightType::kPoint ? glm::translate(mat4(1.0f), light.position)
                                                     : facing(light.position, light.direction);
      node.matrix = matrix(m);
      tinygltf::Value::Object ext{{"light", Value(static_cast<int>(model_.lights.size()) - 1)}};
      node.extensions["KHR_lights_punctual"] = Value(ext);
      root.nodes.push_back(add_node(node));
      use("KHR_lights_punctual");
    }
    summary_.lights = model_.lights.size();
    if (area > 0)
      summary_.dropped.push_back(fmt::format(
          "{} area light(s) as lights (their emitters keep their emissive materials)", area));
    if (scene_.environment) summary_.dropped.push_back("the environment (glTF core has none)");
  }

  const Scene& scene_;
  const GltfLightmapTexture* lightmap_;
  GltfWriteSummary& summary_;
  tinygltf::Model model_;
  std::vector<std::string> used_;
};

}  // namespace

std::vector<uint8_t> encode_png(const std::vector<uint8_t>& bytes, int width, int height,
                                int channels) {
  ILLUM_CHECK(bytes.size() == static_cast<size_t>(width) * height * channels,
              "encode_png: {} bytes for {}x{}x{}", bytes.size(), width, height, channels);
  std::vector<uint8_t> png;
  if (stbi_write_png_to_func(append_png, &png, width, height, channels, bytes.data(),
                             width * channels) == 0 ||
      png.empty())
    throw Error(fmt::format("cannot encode a {}x{} PNG", width, height));
  return png;
}

std::vector<uint8_t> scene_to_glb(const Scene& scene, const GltfLightmapTexture* lightmap,
                                  GltfWriteSummary* summary) {
  GltfWriteSummary local;
  GltfWriteSummary& s = summary != nullptr ? *summary : local;
  s = GltfWriteSummary{};
  tinygltf::Model model = ModelBuilder(scene, lightmap, s).build();
  tinygltf::TinyGLTF writer;
  std::ostringstream stream;
  if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/false, /*writeBinary=*/true))
    throw Error("tinygltf could not serialise the glTF model");
  const std::string bytes = stream.str();
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

}  // namespace illum::exporter
