#include "realtime_options.h"

#include <algorithm>
#include <cmath>

#include "commands.h"
#include "illum/core/params.h"
#include "illum/realtime/technique_registry.h"
#include "illum/scene/lighting_overrides.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

// Shows `choices` in help as IsMember does, and leaves the refusal of another name to
// RenderSettings, which says what it is instead ("a frame pipeline, chosen with --technique").
CLI::Validator listed_choices(const std::vector<std::string>& choices) {
  std::string set;
  for (const std::string& c : choices) set += (set.empty() ? "" : ",") + c;
  return CLI::Validator([](std::string&) { return std::string(); }, "{" + set + "}");
}

}  // namespace

void add_realtime_options(CLI::App* cmd, RealtimeArgs* args) {
  using realtime::TechniqueKind;
  const auto* tonemap = realtime::find_technique("tonemap");
  cmd->add_option("-t,--technique", args->technique, "frame pipeline")
      ->check(CLI::IsMember(realtime::technique_names(TechniqueKind::kFramePipeline)))
      ->capture_default_str();
  cmd->add_option("--shadows", args->shadows, "shadow method")
      ->check(CLI::IsMember(realtime::technique_names(TechniqueKind::kShadowMethod)))
      ->capture_default_str();
  const std::vector<std::string> add_ons = realtime::technique_names(TechniqueKind::kAddOn);
  cmd->add_option("--enable", args->enable,
                  "switch add-ons on (NAME[,NAME], repeatable; `illum frame --list` lists them)")
      ->delimiter(',')
      ->check(listed_choices(add_ons));
  cmd->add_option("--disable", args->disable, "switch add-ons off (NAME[,NAME], repeatable)")
      ->delimiter(',')
      ->check(listed_choices(add_ons));
  cmd->add_option("--tonemap", args->tonemap, "tone mapper: clamp, reinhard, aces, agx")
      ->check(CLI::IsMember(tonemap->param("operator")->choices))
      ->capture_default_str();
  cmd->add_option("--exposure", args->exposure,
                  "a multiplier on the auto exposure (with --fixed-exposure, the whole exposure)")
      ->transform(number(0.0f, 1e6f))
      ->capture_default_str();
  cmd->add_flag("--fixed-exposure", args->fixed_exposure,
                "no auto exposure, --exposure alone scales the radiance (same as --disable "
                "luminance)");
  cmd->add_option("-p,--param", args->params,
                  "technique parameter NAME.key=value (repeatable; `illum frame --list` lists "
                  "them, with the short keys also accepted, e.g. pcf_taps=8, "
                  "bloom_strength=0.5, ambient=[r,g,b] (default: the scene's settings.ambient))");
}

void add_baked_option(CLI::App* cmd, std::vector<std::string>* folders) {
  cmd->add_option("--baked", *folders,
                  "show a folder written by `illum bake` — light-map or PRT, told by its "
                  "manifest; repeatable, one of each kind (replaces the lights it holds; PRT is "
                  "lit by --sun)")
      ->allow_extra_args(false);
}

namespace {

// Every key `-p` takes: NAME.key, the short aliases and the add-ons' switch keys.
std::vector<std::string> param_keys() {
  std::vector<std::string> keys;
  for (const realtime::TechniqueDecl& t : realtime::technique_registry()) {
    if (!t.switch_alias.empty()) keys.push_back(t.switch_alias);
    for (const realtime::ParamDecl& d : t.params) {
      keys.push_back(t.name + "." + d.key);
      if (!d.alias.empty()) keys.push_back(d.alias);
    }
  }
  return keys;
}

// An unknown key is refused here with the nearest known one; the renderer's own message
// only points at the listing.
void check_param_keys(const nlohmann::json& params) {
  const std::vector<std::string> keys = param_keys();
  for (const auto& [key, value] : params.items()) {
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
    const std::string near = nearest_name(key, keys);
    const std::string hint = near.empty() ? "" : fmt::format("; did you mean {}?", near);
    // A NAME.key keeps the registry's reason (no technique NAME, or NAME has no key).
    std::string reason = "unknown parameter";
    if (key.find('.') != std::string::npos) {
      try {
        realtime::param_decl(key);
      } catch (const Error& e) {
        reason = e.what();
      }
    }
    throw Error(fmt::format("-p {}: {}{} (`illum frame --list` lists all {})", key, reason, hint,
                            keys.size()));
  }
}

}  // namespace

void show_sun_on_prt(realtime::RenderSettings* settings, const std::string& sun) {
  Scene light;
  add_sun(light, sun);  // the same X,Y,Z[,E] as every command, checked there
  const vec3 towards = -normalize(light.lights.back().direction);
  const float to_degrees = 180.0f / kPi;
  settings->set("baked.sun_elevation", std::asin(std::clamp(towards.y, -1.0f, 1.0f)) * to_degrees);
  settings->set("baked.sun_azimuth", std::atan2(towards.x, towards.z) * to_degrees);
  settings->set("baked.sun_irradiance", light.lights.back().irradiance.x);
}

realtime::RenderSettings realtime_settings(const RealtimeArgs& args, const Scene& scene,
                                           bool timing) {
  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"baked.sun_azimuth", "--sun X,Y,Z[,E]"},
                               {"baked.sun_elevation", "--sun X,Y,Z[,E]"},
                               {"baked.sun_irradiance", "--sun X,Y,Z[,E]"}});
  refuse_params_of_options(j, {{"technique", "--technique"},
                               {"shadows", "--shadows"},
                               {"tone_mapper", "--tonemap"},
                               {"tonemap.operator", "--tonemap"},
                               {"width", "--width"},
                               {"height", "--height"},
                               {"exposure", "--exposure"},
                               {"tonemap.exposure", "--exposure"}});
  check_param_keys(j);
  realtime::RenderSettings s;
  s.pipeline = args.technique;
  s.shadows = args.shadows;
  for (const std::string& name : args.enable) s.enable(name);
  for (const std::string& name : args.disable) {
    if (std::find(args.enable.begin(), args.enable.end(), name) != args.enable.end())
      throw Error(fmt::format("--enable {0} and --disable {0} contradict each other", name));
    s.disable(name);
  }
  // Short keys may switch an add-on too (bloom_strength=0, auto_exposure=false): they must not
  // undo an explicit --enable / --disable.
  for (const auto& [key, value] : j.items()) s.set_param(key, value);
  for (const std::string& name : args.enable)
    if (!s.active(name))
      throw Error(fmt::format("--enable {} contradicts a -p key that switches it off", name));
  for (const std::string& name : args.disable)
    if (s.active(name))
      throw Error(fmt::format("--disable {} contradicts a -p key that switches it on", name));
  if (args.fixed_exposure) {
    if (std::find(args.enable.begin(), args.enable.end(), "luminance") != args.enable.end())
      throw Error("--fixed-exposure contradicts --enable luminance");
    s.disable("luminance");
  }
  s.set("tonemap.operator", args.tonemap);
  s.set("tonemap.exposure", args.exposure);
  if (!s.values().count("lighting.ambient")) s.set("lighting.ambient", scene.settings.ambient);
  // Timing runs re-render the shadow maps (and rebuild the volumes) every frame so their
  // cost is in every median; an interactive frame does so only when lights change.
  if (timing)
    for (const char* key : {"map.update_period", "vsm.update_period", "volume.update_period"})
      if (!s.values().count(key)) s.set(key, 1);
  s.check();
  return s;
}

}  // namespace illum::cli
