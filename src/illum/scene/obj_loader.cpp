// Wavefront OBJ/MTL through tinyobjloader. One Mesh (and one identity Instance named after
// the object) per (object, material) pair; vertices keep the OBJ's sharing (one vertex per
// distinct position/normal/uv index triple), so smooth normals can be computed where the
// file has none. The MTL → Material mapping is documented in docs/scene-format.md.
#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <tuple>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/loaders.h"
#include "illum/scene/mesh_processing.h"

namespace illum::detail {

namespace {

Color to_color(const tinyobj::real_t* v) {
  return {v[0], v[1], v[2]};
}

std::string clean_texture_name(std::string name) {
  // MTL files written on Windows use backslashes.
  std::replace(name.begin(), name.end(), '\\', '/');
  return name;
}

Material convert_material(const tinyobj::material_t& m, TextureCache& textures,
                          const std::string& mtl_dir) {
  Material out;
  out.name = m.name;
  out.albedo = to_color(m.diffuse);
  out.emission = to_color(m.emission);
  out.opacity = m.dissolve;
  const Color ks = to_color(m.specular);
  const Color tf = to_color(m.transmittance);
  const bool has_specular = max_component(ks) > 0.0f;
  const bool has_diffuse = max_component(out.albedo) > 0.0f;
  if (m.illum == 7 || (m.ior != 1.0f && max_component(tf) > 0.0f)) {
    out.type = MaterialType::kDielectric;
    out.ior = m.ior != 1.0f ? m.ior : 1.5f;  // illum 7 without Ni: ordinary glass
    out.transmittance = max_component(tf) > 0.0f ? tf : Color(1.0f);
    out.specular = Color(1.0f);
  } else if (m.illum == 3 || m.illum == 5 || (has_specular && !has_diffuse)) {
    out.type = MaterialType::kMirror;
    out.specular = has_specular ? ks : Color(1.0f);
  } else if (has_specular) {
    out.type = MaterialType::kPhong;
    out.specular = ks;
    out.exponent = std::max(m.shininess, 0.0f);
  }
  // Roughness for the real-time path: the Phong exponent ↔ Beckmann roughness match
  // α = √(2/(n+2)); diffuse surfaces are fully rough.
  out.roughness = out.type == MaterialType::kPhong     ? std::sqrt(2.0f / (out.exponent + 2.0f))
                  : out.type == MaterialType::kLambert ? 1.0f
                                                       : 0.0f;

  const auto tex = [&](const std::string& name, bool srgb) {
    return name.empty() ? kNoTexture
                        : textures.get(join_path(mtl_dir, clean_texture_name(name)), srgb, m.name);
  };
  out.albedo_texture = tex(m.diffuse_texname, true);
  out.emission_texture = tex(m.emissive_texname, true);
  if (out.emission_texture != kNoTexture && is_black(out.emission)) out.emission = Color(1.0f);
  if (!m.normal_texname.empty()) {
    out.normal_texture = tex(m.normal_texname, false);
    out.normal_scale = m.normal_texopt.bump_multiplier;
  } else if (!m.bump_texname.empty()) {
    out.normal_texture = tex(m.bump_texname, false);
    out.normal_scale = m.bump_texopt.bump_multiplier;
  }
  return out;
}

// tinyobjloader reads "nan" and "inf" as 0 without a word (1e39 does become inf and is
// caught by validate_mesh), so spell-checked numbers are verified here first. A finite
// number in an OBJ has no letters but e/E.
void check_obj_numbers(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.size() < 2 || line[0] != 'v') continue;
    const char kind = line[1];
    if (kind != ' ' && kind != '\t' && kind != 'n' && kind != 't') continue;
    for (size_t i = 2; i < line.size(); ++i) {
      const char c = line[i];
      if (c == '#') break;
      if (std::isalpha(static_cast<unsigned char>(c)) && c != 'e' && c != 'E') {
        if (line.size() > 60) line = line.substr(0, 60) + "...";
        throw Error(fmt::format("{}: line {}: vertex data is not a finite number: '{}'", path,
                                line_number, line));
      }
    }
  }
}

struct KeyHash {
  size_t operator()(const std::tuple<int, int, int>& k) const {
    const auto [a, b, c] = k;
    return std::hash<long long>()((static_cast<long long>(a) * 73856093LL) ^
                                  (static_cast<long long>(b) * 19349663LL) ^
                                  (static_cast<long long>(c) * 83492791LL));
  }
};

}  // namespace

Scene load_obj(const std::string& path, const LoadOptions& options) {
  if (!file_exists(path)) throw Error(fmt::format("{}: cannot open file", path));
  check_obj_numbers(path);
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = parent_dir(path);
  tinyobj::ObjReader reader;
  const bool ok = reader.ParseFromFile(path, config);
  if (!ok) {
    std::string message = reader.Error();
    std::replace(message.begin(), message.end(), '\n', ' ');
    throw Error(fmt::format("{}: cannot parse OBJ: {}", path, message));
  }

  Scene scene;
  scene.source_path = path;
  {
    // tinyobjloader reports a missing .mtl and similar findings as warnings, one per line.
    std::string w = reader.Warning();
    size_t start = 0;
    while (start < w.size()) {
      size_t end = w.find('\n', start);
      if (end == std::string::npos) end = w.size();
      const std::string line = w.substr(start, end - start);
      if (!line.empty()) add_warning(scene, fmt::format("{}: {}", path, line));
      start = end + 1;
    }
  }

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  TextureCache textures(scene, options, path);
  const std::string dir = parent_dir(path);
  for (const tinyobj::material_t& m : reader.GetMaterials())
    scene.materials.push_back(convert_material(m, textures, dir));
  int default_material = -1;  // appended on first use by a face without usemtl

  const size_t nv = attrib.vertices.size() / 3;
  const size_t nn = attrib.normals.size() / 3;
  const size_t nt = attrib.texcoords.size() / 2;
  const auto& shapes = reader.GetShapes();
  for (size_t s = 0; s < shapes.size(); ++s) {
    const tinyobj::shape_t& shape = shapes[s];
    const std::string object = shape.name.empty() ? fmt::format("object{}", s) : shape.name;
    const auto& mesh_in = shape.mesh;
    // Faces grouped by material, in first-use order so mesh order follows the file.
    std::vector<int> order;
    std::map<int, std::vector<size_t>> faces_by_material;
    size_t offset = 0;
    std::vector<size_t> face_offset(mesh_in.num_face_vertices.size());
    for (size_t f = 0; f < mesh_in.num_face_vertices.size(); ++f) {
      face_offset[f] = offset;
      offset += mesh_in.num_face_vertices[f];
      if (mesh_in.num_face_vertices[f] != 3) continue;  // triangulation left a point/line
      const int mat = f < mesh_in.material_ids.size() ? mesh_in.material_ids[f] : -1;
      auto [it, inserted] = faces_by_material.try_emplace(mat);
      if (inserted) order.push_back(mat);
      it->second.push_back(f);
    }
    for (int mat : order) {
      int material = mat;
      if (material < 0 || static_cast<size_t>(material) >= scene.materials.size()) {
        if (default_material < 0) {
          default_material = static_cast<int>(scene.materials.size());
          Material def;
          def.name = "default";
          scene.materials.push_back(def);
        }
        material = default_material;
      }
      Mesh mesh;
      mesh.name =
          order.size() > 1 ? fmt::format("{}/{}", object, scene.materials[material].name) : object;
      mesh.material = material;
      std::unordered_map<std::tuple<int, int, int>, uint32_t, KeyHash> remap;
      bool any_normal = false, any_uv = false;
      const auto& faces = faces_by_material[mat];
      mesh.indices.reserve(3 * faces.size());
      for (size_t f : faces) {
        for (size_t c = 0; c < 3; ++c) {
          const tinyobj::index_t idx = mesh_in.indices[face_offset[f] + c];
          if (idx.vertex_index < 0 || static_cast<size_t>(idx.vertex_index) >= nv)
            throw Error(fmt::format("{}: object '{}' face {} uses vertex {}, but the file has {}",
                                    path, object, f, idx.vertex_index + 1, nv));
          if (idx.normal_index >= 0 && static_cast<size_t>(idx.normal_index) >= nn)
            throw Error(fmt::format("{}: object '{}' face {} uses normal {}, but the file has {}",
                                    path, object, f, idx.normal_index + 1, nn));
          if (idx.texcoord_index >= 0 && static_cast<size_t>(idx.texcoord_index) >= nt)
            throw Error(fmt::format("{}: object '{}' face {} uses uv {}, but the file has {}", path,
                                    object, f, idx.texcoord_index + 1, nt));
          const auto key = std::make_tuple(idx.vertex_index, idx.normal_index, idx.texcoord_index);
          auto [it, inserted] =
              remap.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
          if (inserted) {
            const size_t v = static_cast<size_t>(idx.vertex_index);
            mesh.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1],
                                        attrib.vertices[3 * v + 2]);
            if (idx.normal_index >= 0) {
              const size_t n = static_cast<size_t>(idx.normal_index);
              mesh.normals.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1],
                                        attrib.normals[3 * n + 2]);
              any_normal = true;
            } else {
              mesh.normals.emplace_back(0.0f);  // zero = missing: computed in finalize
            }
            if (idx.texcoord_index >= 0) {
              const size_t t = static_cast<size_t>(idx.texcoord_index);
              mesh.uv0.emplace_back(attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1]);
              any_uv = true;
            } else {
              mesh.uv0.emplace_back(0.0f);
            }
          }
          mesh.indices.push_back(it->second);
        }
      }
      if (!any_normal) mesh.normals.clear();
      if (!any_uv) mesh.uv0.clear();
      // OBJ's v = 0 is the bottom of the image; illum's images have row 0 at the top.
      for (vec2& uv : mesh.uv0) uv.y = 1.0f - uv.y;
      validate_mesh(mesh, path, scene.materials.size());
      Instance inst;
      inst.name = object;
      inst.mesh = static_cast<int>(scene.meshes.size());
      scene.meshes.push_back(std::move(mesh));
      scene.instances.push_back(inst);
    }
  }
  return scene;
}

}  // namespace illum::detail
