#include "illum/scene/lighting_overrides.h"

#include <charconv>
#include <cmath>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/scene/scene_validation.h"

namespace illum {

namespace {

// Comma-separated finite decimal numbers; nullopt-like empty result for anything else.
bool parse_numbers(const std::string& text, std::vector<float>* out) {
  out->clear();
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    float v = 0.0f;
    const char* first = text.data() + start;
    const char* last = text.data() + end;
    const auto r = std::from_chars(first, last, v, std::chars_format::general);
    if (first == last || r.ec != std::errc() || r.ptr != last || !std::isfinite(v)) return false;
    out->push_back(v);
    start = end + 1;
  }
  return true;
}

}  // namespace

void add_sun(Scene& scene, const std::string& value) {
  std::vector<float> n;
  if (!parse_numbers(value, &n) || (n.size() != 3 && n.size() != 4))
    throw Error(
        fmt::format("--sun '{}': expected X,Y,Z (the direction the light travels) or "
                    "X,Y,Z,E (and its irradiance in W/m²)",
                    value));
  const vec3 direction(n[0], n[1], n[2]);
  if (!(glm::length(direction) > 0.0f))
    throw Error(fmt::format("--sun '{}': the direction is zero", value));
  const float irradiance = n.size() == 4 ? n[3] : kPi;
  if (!(irradiance >= 0.0f))
    throw Error(fmt::format("--sun '{}': the irradiance must be ≥ 0", value));
  Light sun;
  sun.name = "sun (--sun)";
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(direction);
  sun.irradiance = Color(irradiance);
  scene.lights.push_back(sun);
}

void set_sky(Scene& scene, const std::string& value) {
  Environment env;
  std::vector<float> n;
  if (parse_numbers(value, &n)) {
    if (n.size() != 1 && n.size() != 3)
      throw Error(
          fmt::format("--sky '{}': expected R,G,B or one radiance V, or an "
                      "equirectangular .hdr/.exr file",
                      value));
    env.constant = n.size() == 1 ? Color(n[0]) : Color(n[0], n[1], n[2]);
    if (!(env.constant.r >= 0.0f && env.constant.g >= 0.0f && env.constant.b >= 0.0f))
      throw Error(fmt::format("--sky '{}': radiance must be ≥ 0", value));
  } else {
    env.path = value;
    // Refuses a missing, truncated or undecodable file and NaN or infinite texels, naming it.
    try {
      env.radiance = read_image(value, /*srgb=*/false);
    } catch (const Error& e) {
      throw Error(fmt::format("--sky: {} (not R,G,B or V either)", e.what()));
    }
    for (size_t i = 0; i < env.radiance.data().size(); ++i)
      if (env.radiance.data()[i] < 0.0f)
        throw Error(fmt::format("--sky {}: negative radiance at texel {}", value,
                                i / size_t(env.radiance.channels())));
  }
  std::erase_if(scene.lights, [](const Light& l) { return l.type == LightType::kEnvironment; });
  scene.environment = std::move(env);
  Light light;
  light.name = "environment";
  light.type = LightType::kEnvironment;
  scene.lights.push_back(light);
}

bool has_any_light(const Scene& scene) {
  return !scene.lights.empty() || scene.environment.has_value();
}

std::string unlit_scene_message(const Scene& scene, const std::string& command,
                                const std::string& consequence) {
  return fmt::format(
      "{}: scene '{}' has no light (no lamp, emissive surface or environment): "
      "{}; add one with --sun X,Y,Z[,E] or --sky R,G,B|FILE",
      command, scene.name, consequence);
}

}  // namespace illum
