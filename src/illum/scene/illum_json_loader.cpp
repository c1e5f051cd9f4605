// illum's own scene files (*.illum.json): geometry from OBJ/glTF files plus the lights,
// camera, environment and settings those formats lack. Read through Params, so every
// unknown key is an error naming the file and the key. Format: docs/scene-format.md.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string_view>

#include "illum/core/error.h"
#include "illum/core/params.h"
#include "illum/scene/load.h"
#include "illum/scene/loaders.h"
#include "illum/scene/mesh_processing.h"
#include "illum/scene/metals.h"
#include "illum/scene/scene_validation.h"

namespace illum::detail {

namespace {

// Reads "transform": {"translate", "rotate_deg" (XYZ Euler, applied x then y then z),
// "scale" (number or [x,y,z])}, and the mesh-level uniform "scale", into one matrix:
// M = T · Rz · Ry · Rx · S · s.
mat4 read_transform(const Params& mesh) {
  mat4 m(1.0f);
  if (mesh.has("transform")) {
    const Params t = mesh.child("transform");
    const vec3 translate = t.get<vec3>("translate", vec3(0.0f));
    const vec3 rot = t.get<vec3>("rotate_deg", vec3(0.0f));
    vec3 scale(1.0f);
    if (t.has("scale")) {
      if (t.raw().at("scale").is_number()) {
        scale = vec3(t.get<float>("scale"));
      } else {
        scale = t.get<vec3>("scale");
      }
    }
    if (scale.x == 0.0f || scale.y == 0.0f || scale.z == 0.0f)
      throw Error(fmt::format("{} must not be zero", t.where("scale")));
    m = glm::translate(m, translate);
    m = glm::rotate(m, radians(rot.z), vec3(0, 0, 1));
    m = glm::rotate(m, radians(rot.y), vec3(0, 1, 0));
    m = glm::rotate(m, radians(rot.x), vec3(1, 0, 0));
    m = glm::scale(m, scale);
  }
  const float s = mesh.get<float>("scale", 1.0f);
  if (!(s > 0.0f)) throw Error(fmt::format("{} must be positive", mesh.where("scale")));
  return glm::scale(m, vec3(s));
}

MaterialType material_type(const Params& p, const std::string& key) {
  const std::string t = p.get<std::string>(key);
  if (t == "lambert") return MaterialType::kLambert;
  if (t == "phong") return MaterialType::kPhong;
  if (t == "blinn") return MaterialType::kBlinn;
  if (t == "mirror") return MaterialType::kMirror;
  if (t == "dielectric") return MaterialType::kDielectric;
  if (t == "conductor") return MaterialType::kConductor;
  throw Error(
      fmt::format("{} = '{}' is not a material type (lambert, phong, blinn, mirror, "
                  "dielectric, conductor)",
                  p.where(key), t));
}

// A colour under the shared rules of scene_validation.h: finite, ≥ 0 and at most `max`
// (1 for reflectances).
Color non_negative_color(const Params& p, const std::string& key, const Color& fallback,
                         float max = std::numeric_limits<float>::max()) {
  const Color c = p.get<vec3>(key, fallback);
  check_color(c, p.where(key), max);
  return c;
}

void override_material(Material& m, const Params& p, TextureCache& textures,
                       const std::string& dir) {
  if (p.has("type")) m.type = material_type(p, "type");
  m.albedo = non_negative_color(p, "albedo", m.albedo, 1.0f);
  m.specular = non_negative_color(p, "specular", m.specular, 1.0f);
  m.exponent = p.get_float_in("exponent", m.exponent, 0.0f, kMaxExponent);
  m.roughness = p.get_float_in("roughness", m.roughness, 0.0f, 1.0f);
  m.ior = p.get_float_in("ior", m.ior, 1.0f, kMaxIor);
  m.transmittance = non_negative_color(p, "transmittance", m.transmittance, 1.0f);
  if (p.has("metal")) {
    // A named metal is a conductor; another type beside it is a contradiction, not a choice.
    if (m.type != MaterialType::kConductor && p.has("type"))
      throw Error(fmt::format("{} = '{}' is a conductor, but {} is '{}'", p.where("metal"),
                              p.get<std::string>("metal"), p.where("type"), to_string(m.type)));
    const std::string name = p.get<std::string>("metal");
    const std::optional<ComplexIndex> metal = named_metal(name);
    if (!metal)
      throw Error(
          fmt::format("{} = '{}' is not a known metal ({})", p.where("metal"), name, kMetalNames));
    m.type = MaterialType::kConductor;
    m.eta = metal->eta;
    m.k = metal->k;
  }
  m.eta = non_negative_color(p, "eta", m.eta);
  m.k = non_negative_color(p, "k", m.k);
  if (p.has("alpha")) {
    m.alpha = p.get_float_in("alpha", m.alpha, 0.0f, 1.0f);
    // The real-time renderers read glTF's perceptual roughness, whose square is α.
    if (!p.has("roughness")) m.roughness = std::sqrt(m.alpha);
  }
  m.emission = non_negative_color(p, "emission", m.emission);
  m.opacity = p.get_float_in("opacity", m.opacity, 0.0f, 1.0f);
  if (p.has("albedo_texture"))
    m.albedo_texture =
        textures.get(join_path(dir, p.get<std::string>("albedo_texture")), true, m.name);
  if (p.has("normal_texture"))
    m.normal_texture =
        textures.get(join_path(dir, p.get<std::string>("normal_texture")), false, m.name);
}

// A non-negative scalar radiometric quantity ("flux", "intensity", "irradiance").
float non_negative(const Params& p, const std::string& key) {
  const float v = p.get<float>(key);
  if (v < 0.0f) throw Error(fmt::format("{} = {} must not be negative", p.where(key), v));
  return v;
}

vec3 unit_direction(const Params& p, const std::string& key) {
  const vec3 d = p.get<vec3>(key);
  const float len = glm::length(d);
  if (!(len > 0.0f)) throw Error(fmt::format("{} must not be a zero vector", p.where(key)));
  return d / len;
}

Light read_light(const Params& p, size_t index) {
  Light light;
  const std::string type = p.get<std::string>("type");
  light.name = p.get<std::string>("name", fmt::format("light{}", index));
  const Color color = non_negative_color(p, "color", Color(1.0f));
  const bool has_flux = p.has("flux"), has_intensity = p.has("intensity");
  if ((type == "point" || type == "spot") && has_flux == has_intensity)
    throw Error(fmt::format("{}: a {} light needs exactly one of 'flux' (W) or 'intensity' (W/sr)",
                            p.where("type"), type));
  if (type == "point") {
    light.type = LightType::kPoint;
    light.position = p.get<vec3>("position");
    const float i =
        has_flux ? non_negative(p, "flux") / (4.0f * kPi) : non_negative(p, "intensity");
    light.intensity = i * color;
  } else if (type == "spot") {
    light.type = LightType::kSpot;
    light.position = p.get<vec3>("position");
    light.direction = unit_direction(p, "direction");
    const float half = p.get<float>("half_angle_deg");
    if (!(half > 0.0f && half <= 90.0f))
      throw Error(fmt::format("{} = {} must lie in (0, 90]", p.where("half_angle_deg"), half));
    light.cone_half_angle = radians(half);
    const float i = has_flux ? non_negative(p, "flux") / light.cone_solid_angle()
                             : non_negative(p, "intensity");
    light.intensity = i * color;
  } else if (type == "directional" || type == "sun") {
    light.type = LightType::kDirectional;
    light.direction = unit_direction(p, "direction");
    light.irradiance = non_negative(p, "irradiance") * color;
  } else {
    throw Error(fmt::format("{} = '{}' is not a light type (point, spot, directional, sun)",
                            p.where("type"), type));
  }
  if (p.has("range")) light.range = p.get_float_in("range", 0.0f, 0.0f, 1e30f);
  return light;
}

// `"lightmap": {"texel_size": s}` of a mesh entry (0 when absent): metres in the scene's
// final units, in (0, kMaxLightmapTexelSize].
float read_lightmap_texel_size(const Params& entry) {
  if (!entry.has("lightmap")) return 0.0f;
  const Params lightmap = entry.child("lightmap");
  const float s = lightmap.get<float>("texel_size");
  if (!(s > 0.0f && s <= kMaxLightmapTexelSize))
    throw Error(fmt::format("{} = {} must be in (0, {}] metres per texel",
                            lightmap.where("texel_size"), s, kMaxLightmapTexelSize));
  return s;
}

}  // namespace

// A mesh path starting with this is inside shared_scenes_dir() (load.h), not the scene
// file's folder: large models kept outside the repository, wherever they are installed.
constexpr std::string_view kSharedScenesPrefix = "${shared_scenes}/";

Scene load_illum_json(const std::string& path, const LoadOptions& options) {
  const Params root = Params::from_file(path);
  const std::string dir = parent_dir(path);
  Scene scene;
  scene.name = root.get<std::string>("name", "");
  root.get<std::string>("description", "");  // free text for people; read so it is known
  TextureCache textures(scene, options, path);

  if (root.has("meshes")) {
    for (const Params& entry : root.children("meshes")) {
      const std::string given = entry.get<std::string>("file");
      const bool shared = given.starts_with(kSharedScenesPrefix);
      const std::string file =
          shared ? join_path(shared_scenes_dir(), given.substr(kSharedScenesPrefix.size()))
                 : join_path(dir, given);
      const std::string ext = lower_extension(file);
      if (ext != ".obj" && ext != ".gltf" && ext != ".glb")
        throw Error(fmt::format("{} = '{}' must be an .obj, .gltf or .glb file",
                                entry.where("file"), given));
      // A shared mesh is missing on any fresh checkout or installed copy: say where it was
      // looked for and how to provide it, in the one line a user sees.
      if (!file_exists(file) && shared) {
        const std::string relative = given.substr(kSharedScenesPrefix.size());
        throw Error(fmt::format(
            "{}: mesh '{}' not found: it is kept outside the repository, with the shared "
            "scenes; copy their '{}' folder into '{}', or set ILLUM_SHARED_SCENES to a folder "
            "that holds '{}'",
            path, file, std::filesystem::path(relative).parent_path().string(), shared_scenes_dir(),
            relative));
      }
      if (!file_exists(file))
        throw Error(fmt::format("{}: cannot open file '{}' ({})", path, file, entry.where("file")));
      Scene part = ext == ".obj" ? load_obj(file, options) : load_gltf(file, options);
      // Checked here too, so a bad value names the file it is in (an MTL's Kd, say), not
      // only this scene file as finalize_scene would.
      validate_scene_values(part, file);
      const mat4 transform = read_transform(entry);
      const bool dynamic = entry.get<bool>("dynamic", false);
      const float lightmap_texel_size = read_lightmap_texel_size(entry);

      // Drop hidden objects (by instance or mesh name); an unknown name is a typo.
      if (entry.has("hide")) {
        const auto hide = entry.get<std::vector<std::string>>("hide");
        for (const std::string& h : hide) {
          const bool found = std::any_of(
              part.instances.begin(), part.instances.end(),
              [&](const Instance& i) { return i.name == h || part.meshes[i.mesh].name == h; });
          if (!found)
            throw Error(
                fmt::format("{}: no object named '{}' in {}", entry.where("hide"), h, file));
        }
        std::erase_if(part.instances, [&](const Instance& i) {
          return std::find(hide.begin(), hide.end(), i.name) != hide.end() ||
                 std::find(hide.begin(), hide.end(), part.meshes[i.mesh].name) != hide.end();
        });
      }

      // Merge: meshes used by one instance get the whole transform baked in (so their
      // vertices are in metres, like the JSON's lights and camera); shared meshes keep
      // theirs in the instances. Unreferenced (hidden) meshes are left out.
      std::vector<int> uses(part.meshes.size(), 0);
      for (const Instance& i : part.instances) ++uses[i.mesh];
      std::vector<int> mesh_map(part.meshes.size(), -1);
      const int material_offset = static_cast<int>(scene.materials.size());
      for (size_t m = 0; m < part.meshes.size(); ++m) {
        if (uses[m] == 0) continue;
        mesh_map[m] = static_cast<int>(scene.meshes.size());
        part.meshes[m].material += material_offset;
        scene.meshes.push_back(std::move(part.meshes[m]));
      }
      for (Instance inst : part.instances) {
        const int original = inst.mesh;
        inst.transform = transform * inst.transform;
        inst.mesh = mesh_map[original];
        inst.dynamic = dynamic;
        inst.lightmap_texel_size = lightmap_texel_size;
        if (uses[original] == 1) {
          transform_mesh(scene.meshes[inst.mesh], inst.transform);
          inst.transform = mat4(1.0f);
        }
        scene.instances.push_back(inst);
      }
      // Textures: renumber into the merged list.
      const int texture_offset = static_cast<int>(scene.textures.size());
      for (Material& m : part.materials) {
        for (int* t :
             {&m.albedo_texture, &m.roughness_texture, &m.emission_texture, &m.normal_texture}) {
          if (*t != kNoTexture) *t += texture_offset;
        }
        scene.materials.push_back(m);
      }
      for (Texture& t : part.textures) scene.textures.push_back(std::move(t));
      for (Light light : part.lights) {
        light.position = vec3(transform * vec4(light.position, 1.0f));
        const vec3 d = mat3(transform) * light.direction;
        light.direction = glm::length(d) > 0.0f ? glm::normalize(d) : light.direction;
        scene.lights.push_back(light);
      }
      if (part.camera && !scene.camera) {
        Camera cam = *part.camera;
        cam.position = vec3(transform * vec4(cam.position, 1.0f));
        cam.look_at = vec3(transform * vec4(cam.look_at, 1.0f));
        cam.up = glm::normalize(mat3(transform) * cam.up);
        scene.camera = cam;
      }
      for (std::string& w : part.warnings) scene.warnings.push_back(std::move(w));
    }
  }
  if (scene.materials.empty()) {
    Material def;
    def.name = "default";
    scene.materials.push_back(def);
  }

  if (root.has("materials")) {
    const Params mats = root.child("materials");
    for (const auto& [key, value] : mats.raw().items()) {
      const Params p = mats.child(key);
      bool found = false;
      for (Material& m : scene.materials) {
        if (m.name != key) continue;
        override_material(m, p, textures, dir);
        found = true;
      }
      if (!found)
        throw Error(
            fmt::format("{}: no material named '{}' in the scene's meshes", mats.where(key), key));
    }
  }

  if (root.has("lights")) {
    const auto lights = root.children("lights");
    for (size_t i = 0; i < lights.size(); ++i) scene.lights.push_back(read_light(lights[i], i));
  }

  if (root.has("environment")) {
    const Params e = root.child("environment");
    Environment env;
    if (e.has("file") == e.has("constant"))
      throw Error(fmt::format("{}: give exactly one of 'file' or 'constant'", e.where("file")));
    bool have_map = true;
    if (e.has("file")) {
      env.path = join_path(dir, e.get<std::string>("file"));
      if (!file_exists(env.path)) {
        missing_texture(
            scene, options,
            fmt::format("{}: environment map '{}' not found", e.where("file"), env.path));
        have_map = false;
      } else {
        try {
          // The reader refuses NaN and infinite texels (naming the texel).
          env.radiance = read_image(env.path, /*srgb=*/false);
        } catch (const Error& error) {
          missing_texture(scene, options,
                          fmt::format("{}: environment map: {}", e.where("file"), error.what()));
          have_map = false;
        }
      }
      // Importance sampling builds a distribution from these values: a negative texel is bad
      // input here, not a crash later.
      for (size_t i = 0; i < env.radiance.data().size(); ++i) {
        if (env.radiance.data()[i] < 0.0f) {
          const size_t texel = i / static_cast<size_t>(env.radiance.channels());
          throw Error(fmt::format("{}: environment map '{}' has a negative value at texel ({}, {})",
                                  e.where("file"), env.path, texel % env.radiance.width(),
                                  texel / env.radiance.width()));
        }
      }
    } else {
      env.constant = non_negative_color(e, "constant", Color(0.0f));
    }
    env.scale = e.get_float_in("scale", 1.0f, 0.0f, 1e30f);
    env.rotation_y = radians(e.get<float>("rotation_deg", 0.0f));
    if (have_map) {  // without its map (allowed missing) the scene has no environment
      scene.environment = std::move(env);
      Light light;
      light.name = "environment";
      light.type = LightType::kEnvironment;
      scene.lights.push_back(light);
    }
  }

  if (root.has("camera")) {
    const Params c = root.child("camera");
    Camera cam;
    cam.position = c.get<vec3>("position");
    cam.look_at = c.get<vec3>("look_at");
    cam.up = c.get<vec3>("up", vec3(0.0f, 1.0f, 0.0f));
    const float fov = c.get<float>("fov_y_deg", 45.0f);
    if (!(fov > 0.0f && fov < 180.0f))
      throw Error(fmt::format("{} = {} must lie in (0, 180)", c.where("fov_y_deg"), fov));
    cam.fov_y = radians(fov);
    const vec3 forward = cam.look_at - cam.position;
    if (glm::length(forward) == 0.0f || glm::length(glm::cross(forward, cam.up)) == 0.0f)
      throw Error(
          fmt::format("{}: position, look_at and up must span a view (distinct, up not "
                      "parallel to the view direction)",
                      c.where("look_at")));
    scene.camera = cam;
  }

  if (root.has("settings")) {
    const Params s = root.child("settings");
    scene.settings.width = s.get_int_in("width", scene.settings.width, 1, 1 << 15);
    scene.settings.height = s.get_int_in("height", scene.settings.height, 1, 1 << 15);
    scene.settings.spp = s.get_int_in("spp", scene.settings.spp, 1, 1 << 24);
    scene.settings.max_bounces = s.get_int_in("max_bounces", scene.settings.max_bounces, 0, 1024);
    scene.settings.ambient = non_negative_color(s, "ambient", scene.settings.ambient);
  }

  root.check_all_used();
  return scene;
}

}  // namespace illum::detail
