// Wavefront OBJ/MTL through tinyobjloader. One Mesh (and one identity Instance named after
// the object) per (object, material) pair; vertices keep the OBJ's sharing (one vertex per
// distinct position/normal/uv index triple), so smooth normals can be computed where the
// file has none. The MTL → Material mapping is documented in docs/scene-format.md.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/loaders.h"
#include "illum/scene/mesh_processing.h"

namespace illum::detail {

namespace {

// The most vertices one face may have (see check_obj_text).
constexpr size_t kMaxObjFaceVertices = 1024;

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

std::string read_text_file(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open {}", path, what));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(fmt::format("{}: cannot read {}", path, what));
  return text.str();
}

// A line of an OBJ or MTL file, shortened for a message.
std::string quoted(std::string_view line) {
  std::string s(line.substr(0, 60));
  if (line.size() > 60) s += "...";
  return fmt::format("'{}'", s);
}

// Splits `line` at spaces and tabs, up to a '#' comment.
std::vector<std::string_view> tokens_of(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    i = line.find_first_not_of(" \t\r", i);
    if (i == std::string_view::npos || line[i] == '#') break;
    const size_t end = std::min(line.find_first_of(" \t\r", i), line.size());
    out.push_back(line.substr(i, end - i));
    i = end;
  }
  return out;
}

// A number tinyobjloader reads as the same finite float: decimal digits, sign, point and an
// exponent only (tinyobjloader reads "nan", "inf" and hex as 0 without a word, and 1e39 or
// 400 digits as infinity).
bool is_finite_float(std::string_view token) {
  for (const char c : token)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.' ||
          c == 'e' || c == 'E'))
      return false;
  const std::string s(token);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v) &&
         std::abs(v) <= std::numeric_limits<float>::max();
}

// One line at a time over a file's text, with its number, for the checks below.
template <typename F>
void for_each_line(const std::string& text, F&& f) {
  size_t start = 0, number = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    const size_t lead = line.find_first_not_of(" \t");
    f(++number, lead == std::string_view::npos ? std::string_view() : line.substr(lead));
    start = end + 1;
  }
}

void check_text(const std::string& text, const std::string& path, const char* what) {
  const size_t nul = text.find('\0');
  if (nul != std::string::npos)
    throw Error(fmt::format("{}: not a text {} file (a NUL byte at offset {})", path, what, nul));
}

// Checks an OBJ file's text before tinyobjloader parses it, so errors name the line: numbers
// in v/vn/vt lines (finite floats), face, line and point indices (integers, not 0, within the
// vertices the file has; negative ones relative to those defined so far), and the vertex count
// of a face (tinyobjloader's ear clipping takes time quadratic in it: a few milliseconds at
// the limit, ~10^6 times that for a face of 10^6 vertices). Returns the file names of every
// mtllib line.
std::vector<std::string> check_obj_text(const std::string& text, const std::string& path) {
  check_text(text, path, "OBJ");
  int64_t total[3] = {0, 0, 0};  // v, vt, vn
  for_each_line(text, [&](size_t, std::string_view line) {
    if (line.size() < 2 || line[0] != 'v') return;
    const int kind = line[1] == ' ' || line[1] == '\t' ? 0
                     : line[1] == 't'                  ? 1
                     : line[1] == 'n'                  ? 2
                                                       : -1;
    if (kind >= 0) ++total[kind];
  });
  int64_t so_far[3] = {0, 0, 0};
  std::vector<std::string> mtl_files;
  for_each_line(text, [&](size_t number, std::string_view line) {
    auto fail = [&](const std::string& what) {
      throw Error(fmt::format("{}: line {}: {}: {}", path, number, what, quoted(line)));
    };
    if (line.size() < 2) return;
    const char kind = line[1];
    if (line[0] == 'v' && (kind == ' ' || kind == '\t' || kind == 'n' || kind == 't')) {
      const auto numbers = tokens_of(line.substr(2));
      for (std::string_view n : numbers)
        if (!is_finite_float(n)) fail(fmt::format("'{}' is not a finite number", n.substr(0, 40)));
      ++so_far[kind == 't' ? 1 : kind == 'n' ? 2 : 0];
      return;
    }
    if ((line[0] == 'f' || line[0] == 'l' || line[0] == 'p') && (kind == ' ' || kind == '\t')) {
      const auto corners = tokens_of(line.substr(2));
      if (line[0] == 'f' && corners.size() > kMaxObjFaceVertices)
        fail(fmt::format("a face of {} vertices (illum triangulates at most {})", corners.size(),
                         kMaxObjFaceVertices));
      static const char* const kWhat[3] = {"vertex", "uv", "normal"};
      for (std::string_view corner : corners) {
        int slot = 0;
        size_t i = 0;
        while (i <= corner.size() && slot < 3) {
          const size_t end = std::min(corner.find('/', i), corner.size());
          std::string_view index = corner.substr(i, end - i);
          if (!index.empty() && index[0] == '+') index.remove_prefix(1);  // atoi takes "+3"
          if (!(index.empty() && slot > 0)) {
            int64_t value = 0;
            const auto [ptr, ec] =
                std::from_chars(index.data(), index.data() + index.size(), value);
            if (ec != std::errc() || ptr != index.data() + index.size() || index.empty())
              fail(fmt::format("'{}' is not a {} index", corner.substr(0, 40), kWhat[slot]));
            if (value == 0) fail(fmt::format("{} index 0 (OBJ counts from 1)", kWhat[slot]));
            if (value > total[slot] || (value < 0 && -value > so_far[slot]))
              fail(fmt::format("{} {} is out of range (the file has {}, {} before this line)",
                               kWhat[slot], value, total[slot], so_far[slot]));
          }
          ++slot;
          i = end + 1;
        }
        if (i <= corner.size())
          fail(fmt::format("'{}' has more than three indices", corner.substr(0, 40)));
      }
      return;
    }
    if (line.substr(0, 6) == "mtllib" && line.size() > 6 && (line[6] == ' ' || line[6] == '\t')) {
      // tinyobjloader's own splitting: at spaces, with '\\' escaping the next character.
      std::string name;
      bool escaping = false;
      for (const char c : line.substr(7)) {
        if (c == '#' && !escaping) break;
        if (escaping) {
          escaping = false;
        } else if (c == '\\') {
          escaping = true;
          continue;
        } else if (c == ' ' || c == '\r') {
          if (!name.empty()) mtl_files.push_back(name);
          name.clear();
          continue;
        }
        name += c;
      }
      if (!name.empty()) mtl_files.push_back(name);
    }
  });
  return mtl_files;
}

// MTL statements whose values are numbers; tinyobjloader reads anything else there as 0.
bool is_numeric_mtl_key(std::string_view key) {
  static const char* const kKeys[] = {"Ka", "Kd",  "Ks",    "Ke",     "Kt",       "Tf", "Ns",
                                      "Ni", "d",   "Tr",    "illum",  "Pr",       "Pm", "Ps",
                                      "Pc", "Pcr", "aniso", "anisor", "sharpness"};
  return std::find(std::begin(kKeys), std::end(kKeys), key) != std::end(kKeys);
}

// Numbers in an MTL file must be finite floats (and a texture's -bm bump multiplier, the one
// texture option illum uses); errors name the .mtl file and line.
void check_mtl_text(const std::string& text, const std::string& path) {
  check_text(text, path, "MTL");
  for_each_line(text, [&](size_t number, std::string_view line) {
    const auto tokens = tokens_of(line);
    if (tokens.empty()) return;
    for (size_t i = 1; i < tokens.size(); ++i) {
      const bool texture =
          tokens[0].substr(0, 4) == "map_" || tokens[0] == "bump" || tokens[0] == "norm";
      const bool numeric = is_numeric_mtl_key(tokens[0]) || (texture && tokens[i - 1] == "-bm");
      if (numeric && !is_finite_float(tokens[i]))
        throw Error(fmt::format("{}: line {}: '{}' is not a finite number: {}", path, number,
                                tokens[i].substr(0, 40), quoted(line)));
    }
  });
}

// Hands tinyobjloader the .mtl files from the OBJ's folder after checking their numbers, and
// remembers which were missing (tinyobjloader only warns about them).
class MtlReader : public tinyobj::MaterialReader {
 public:
  explicit MtlReader(std::string dir) : dir_(std::move(dir)) {}
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string* warn, std::string* err) override {
    const std::string file = join_path(dir_, name);
    if (!file_exists(file)) return false;
    try {
      const std::string text = read_text_file(file, "material file");
      check_mtl_text(text, file);
      std::istringstream in(text);
      tinyobj::LoadMtl(names, materials, &in, warn, err);
      return true;
    } catch (const Error& e) {
      // Not thrown through tinyobjloader's frames; load_obj rethrows it.
      if (error_.empty()) error_ = e.what();
      return false;
    }
  }
  const std::string& error() const { return error_; }

 private:
  std::string dir_;
  std::string error_;
};

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
  const std::string text = read_text_file(path, "file");
  const std::vector<std::string> mtl_files = check_obj_text(text, path);
  const std::string dir = parent_dir(path);

  Scene scene;
  scene.source_path = path;
  // A missing .mtl is a missing file like a missing texture: its materials carry the colours
  // and textures, and the scene would silently render in default grey. Every file an mtllib
  // line names must exist; --allow-missing-textures renders with default materials instead.
  bool mtl_missing = false;
  for (const std::string& name : mtl_files) {
    const std::string file = join_path(dir, name);
    if (file_exists(file)) continue;
    mtl_missing = true;
    missing_texture(scene, options,
                    fmt::format("{}: material file '{}' (mtllib) not found", path, file));
  }

  MtlReader mtl_reader(dir);
  tinyobj::attrib_t attrib_data;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings, errors;
  std::istringstream in(text);
  const bool ok = tinyobj::LoadObj(&attrib_data, &shapes, &materials, &warnings, &errors, &in,
                                   &mtl_reader, /*triangulate=*/true,
                                   /*default_vcols_fallback=*/false);
  if (!mtl_reader.error().empty()) throw Error(mtl_reader.error());
  if (!ok) {
    std::replace(errors.begin(), errors.end(), '\n', ' ');
    throw Error(fmt::format("{}: cannot parse OBJ: {}", path, errors));
  }

  const tinyobj::attrib_t& attrib = attrib_data;
  TextureCache textures(scene, options, path);
  for (const tinyobj::material_t& m : materials)
    scene.materials.push_back(convert_material(m, textures, dir));
  // tinyobjloader's warnings, one per line, after the materials (whose missing textures are
  // errors, which must come alone). A missing .mtl was reported above; its consequences
  // (unknown usemtl names, "use default material") are not reported again.
  size_t start = 0;
  while (start < warnings.size()) {
    size_t end = warnings.find('\n', start);
    if (end == std::string::npos) end = warnings.size();
    const std::string line = warnings.substr(start, end - start);
    start = end + 1;
    if (line.empty() || line.rfind("Failed to load material file", 0) == 0) continue;
    if (mtl_missing && line.find("not found in .mtl") != std::string::npos) continue;
    add_warning(scene, fmt::format("{}: {}", path, line));
  }

  int default_material = -1;  // appended on first use by a face without usemtl

  const size_t nv = attrib.vertices.size() / 3;
  const size_t nn = attrib.normals.size() / 3;
  const size_t nt = attrib.texcoords.size() / 2;
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
