// `illum info SCENE`: what a scene contains, as a person or a script (--json) reads it.
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "illum/scene/load.h"

namespace illum::cli {

namespace {

nlohmann::json describe(const Scene& scene) {
  std::map<std::string, int> material_types, light_types;
  for (const auto& m : scene.materials) material_types[to_string(m.type)]++;
  for (const auto& l : scene.lights) light_types[to_string(l.type)]++;
  size_t vertices = 0;
  for (const auto& inst : scene.instances) vertices += scene.meshes[inst.mesh].vertex_count();
  const Bounds3 b = scene.bounds();
  nlohmann::json j;
  j["name"] = scene.name;
  j["source"] = scene.source_path;
  j["triangles"] = scene.triangle_count();
  j["vertices"] = vertices;
  j["meshes"] = scene.meshes.size();
  j["instances"] = scene.instances.size();
  j["materials"] = scene.materials.size();
  j["material_types"] = material_types;
  // Every texture the file holds that illum read: the materials' and the light-map.
  j["textures"] = scene.textures.size() + (scene.lightmap ? 1 : 0);
  if (scene.lightmap) {
    const SceneLightmap& map = *scene.lightmap;
    j["lightmap"] = {
        {"encoding", map.encoding},    {"range", map.range}, {"tone", map.tone},
        {"basis", map.basis},          {"layer", map.layer}, {"width", map.image.width()},
        {"height", map.image.height()}};
  }
  j["lights"] = scene.lights.size();
  j["light_types"] = light_types;
  j["environment"] = scene.environment.has_value();
  j["camera"] = scene.camera.has_value();
  if (!b.empty()) {
    j["bounds_min"] = {b.min.x, b.min.y, b.min.z};
    j["bounds_max"] = {b.max.x, b.max.y, b.max.z};
  }
  j["warnings"] = scene.warnings;
  return j;
}

void print_text(const nlohmann::json& j) {
  auto counts = [](const nlohmann::json& m) {
    std::string s;
    for (const auto& [k, v] : m.items())
      s += fmt::format("{}{} {}", s.empty() ? "" : ", ", v.get<int>(), k);
    return s.empty() ? std::string("none") : s;
  };
  std::printf("scene       %s (%s)\n", j["name"].get<std::string>().c_str(),
              j["source"].get<std::string>().c_str());
  std::printf("triangles   %zu in %zu instances of %zu meshes (%zu vertices)\n",
              j["triangles"].get<size_t>(), j["instances"].get<size_t>(), j["meshes"].get<size_t>(),
              j["vertices"].get<size_t>());
  std::printf("materials   %zu: %s\n", j["materials"].get<size_t>(),
              counts(j["material_types"]).c_str());
  std::printf("textures    %zu%s\n", j["textures"].get<size_t>(),
              j.contains("lightmap") ? " (one is the light-map)" : "");
  if (j.contains("lightmap")) {
    const auto& m = j["lightmap"];
    const std::string tone = m["tone"].get<std::string>();
    const std::string basis = m["basis"].get<std::string>();
    std::printf("light-map   %dx%d %s, range %.6g, %s, on TEXCOORD_1 (from a %s bake: %s)\n",
                m["width"].get<int>(), m["height"].get<int>(),
                m["encoding"].get<std::string>().c_str(), m["range"].get<double>(),
                tone == "none" ? "linear E/π" : ("tone-mapped " + tone).c_str(),
                basis.empty() ? "light-map" : basis.c_str(), m["layer"].get<std::string>().c_str());
  }
  std::printf("lights      %zu: %s\n", j["lights"].get<size_t>(), counts(j["light_types"]).c_str());
  std::printf("environment %s\n", j["environment"].get<bool>() ? "yes" : "no");
  std::printf("camera      %s\n",
              j["camera"].get<bool>() ? "yes" : "no (a framing camera is used)");
  if (j.contains("bounds_min")) {
    const auto& lo = j["bounds_min"];
    const auto& hi = j["bounds_max"];
    std::printf("bounds      (%.4g, %.4g, %.4g) .. (%.4g, %.4g, %.4g) m\n", lo[0].get<double>(),
                lo[1].get<double>(), lo[2].get<double>(), hi[0].get<double>(), hi[1].get<double>(),
                hi[2].get<double>());
  } else {
    std::printf("bounds      empty\n");
  }
  std::printf("warnings    %zu\n", j["warnings"].size());
  for (const auto& w : j["warnings"]) std::printf("  - %s\n", w.get<std::string>().c_str());
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "info", "Print what a scene contains: triangles, lights, materials, bounds, warnings");
  auto scene = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("scene", *scene, "scene file (.obj, .gltf, .glb, .illum.json) or built-in name")
      ->required();
  cmd->add_flag("--json", *json, "print JSON instead of text");
  auto load = std::make_shared<LoadOptions>();
  add_load_options(cmd, load.get());
  cmd->callback([scene, json, load] {
    const Scene s = load_scene(*scene, *load);
    const auto j = describe(s);
    if (*json)
      std::printf("%s\n", j.dump(2).c_str());
    else
      print_text(j);
  });
}

}  // namespace illum::cli
