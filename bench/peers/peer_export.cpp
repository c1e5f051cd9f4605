#include "peer_export.h"

#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "converge_stats.h"
#include "illum/core/error.h"
#include "illum/scene/scene.h"
#include "suites.h"

namespace illum::bench {
namespace {

nlohmann::json vec(const vec3& v) {
  return {v.x, v.y, v.z};
}

nlohmann::json color(const Color& c) {
  return {c.r, c.g, c.b};
}

nlohmann::json material_json(const Scene& scene, const Material& m) {
  nlohmann::json j;
  j["name"] = m.name;
  if (m.type == MaterialType::kLambert) {
    j["type"] = "diffuse";
    j["albedo"] = color(m.albedo);
  } else if (m.type == MaterialType::kMirror) {
    j["type"] = "mirror";
    j["albedo"] = color(m.specular);
  } else {
    throw Error(fmt::format(
        "converge: material '{}' is {}, which the Cycles peer does not map (Lambert and mirror "
        "only; bench/peers/README.md)",
        m.name, to_string(m.type)));
  }
  j["albedo_texture"] = nullptr;
  if (m.albedo_texture != kNoTexture) {
    const Texture& t = scene.textures[static_cast<size_t>(m.albedo_texture)];
    j["albedo_texture"] = std::filesystem::absolute(t.path).string();
    j["albedo_texture_srgb"] = t.srgb;
  }
  if (m.emission_texture != kNoTexture)
    throw Error(
        fmt::format("converge: material '{}' has an emission texture (not mapped)", m.name));
  // Cycles' emission strength S gives radiance S × colour: illum's L_e as it is. illum emits
  // from the front face only; the peer script masks Cycles' back face.
  j["emission"] = color(m.emission);
  return j;
}

nlohmann::json light_json(const Light& l) {
  nlohmann::json j;
  j["name"] = l.name;
  j["position"] = vec(l.position);
  j["direction"] = vec(l.direction);
  switch (l.type) {
    case LightType::kPoint:
      j["type"] = "point";
      j["power_w"] = {cycles_point_power(l.intensity.r), cycles_point_power(l.intensity.g),
                      cycles_point_power(l.intensity.b)};
      break;
    case LightType::kSpot:
      if (l.cosine_falloff)
        throw Error(fmt::format("converge: spot '{}' has a cosine falloff (not mapped)", l.name));
      // Cycles 3.4's spot falls off as cos θ inside its cone; a flat IES profile on a point
      // light is illum's uniform cone.
      j["type"] = "ies_spot";
      j["cone_half_angle"] = l.cone_half_angle;
      j["power_w"] = {cycles_ies_spot_power(l.intensity.r), cycles_ies_spot_power(l.intensity.g),
                      cycles_ies_spot_power(l.intensity.b)};
      break;
    case LightType::kDirectional:
      j["type"] = "sun";  // Cycles' sun strength is the irradiance in W/m², as illum's
      j["strength"] = color(l.irradiance);
      break;
    case LightType::kArea:
      return nullptr;  // its instance's emissive material carries it
    case LightType::kEnvironment:
      return nullptr;  // Scene::environment, below
  }
  return j;
}

template <typename T>
void put(std::ofstream& out, const std::vector<T>& v) {
  out.write(reinterpret_cast<const char*>(v.data()),
            static_cast<std::streamsize>(v.size() * sizeof(T)));
}

}  // namespace

void export_peer_scene(const Scene& scene, const Camera& camera, const PeerRenderSettings& settings,
                       const std::string& stem) {
  nlohmann::json j;
  j["format"] = "illum-peer-scene 1";
  j["scene"] = scene.name;
  j["width"] = settings.width;
  j["height"] = settings.height;
  j["max_bounces_illum"] = settings.max_bounces;
  j["cycles_max_bounces"] = cycles_max_bounces(settings.max_bounces);
  j["cycles_ies_scale"] = kCyclesIesScale;
  j["camera"] = {{"position", vec(camera.position)},
                 {"look_at", vec(camera.look_at)},
                 {"up", vec(camera.up)},
                 {"fov_y", camera.fov_y}};
  j["materials"] = nlohmann::json::array();
  for (const Material& m : scene.materials) j["materials"].push_back(material_json(scene, m));
  j["lights"] = nlohmann::json::array();
  for (const Light& l : scene.lights)
    if (nlohmann::json lj = light_json(l); !lj.is_null()) j["lights"].push_back(lj);
  j["background"] = color(Color(0.0f));
  if (scene.environment) {
    if (!scene.environment->radiance.empty())
      throw Error("converge: environment maps are not mapped to the Cycles peer");
    j["background"] = color(scene.environment->constant * scene.environment->scale);
  }

  const std::string bin_path = stem + ".bin";
  std::ofstream bin(bin_path, std::ios::binary);
  if (!bin) throw Error(fmt::format("{}: cannot write", bin_path));
  j["geometry"] = std::filesystem::path(bin_path).filename().string();
  j["meshes"] = nlohmann::json::array();
  size_t offset = 0;
  for (const Instance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    const mat3 normal_matrix = glm::transpose(glm::inverse(mat3(inst.transform)));
    std::vector<float> p, n, uv;
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      const vec3 wp = vec3(inst.transform * vec4(mesh.positions[v], 1.0f));
      const vec3 wn = glm::normalize(normal_matrix * mesh.normals[v]);
      p.insert(p.end(), {wp.x, wp.y, wp.z});
      n.insert(n.end(), {wn.x, wn.y, wn.z});
      // illum's v = 0 is the image's top row, Blender's the bottom row.
      if (!mesh.uv0.empty()) uv.insert(uv.end(), {mesh.uv0[v].x, 1.0f - mesh.uv0[v].y});
    }
    put(bin, p);
    put(bin, n);
    put(bin, uv);
    put(bin, mesh.indices);
    j["meshes"].push_back({{"name", inst.name.empty() ? mesh.name : inst.name},
                           {"material", mesh.material},
                           {"vertices", mesh.vertex_count()},
                           {"triangles", mesh.triangle_count()},
                           {"has_uv", !mesh.uv0.empty()},
                           {"offset", offset}});
    offset +=
        (p.size() + n.size() + uv.size()) * sizeof(float) + mesh.indices.size() * sizeof(uint32_t);
  }
  if (!bin.flush()) throw Error(fmt::format("{}: write failed", bin_path));
  write_json(stem + ".json", j);
}

}  // namespace illum::bench
