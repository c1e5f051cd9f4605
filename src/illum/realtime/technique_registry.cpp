#include "illum/realtime/technique_registry.h"

#include "illum/core/error.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

const std::vector<TechniqueDecl>& technique_registry() {
  // The one list of techniques. Within a kind, the order is the frame's: add-ons run in
  // this order (tone mapping last).
  static const std::vector<TechniqueDecl> registry = {
      lighting_globals(),   scene_draw_globals(),      forward_technique(),
      deferred_technique(), no_shadows_technique(),    shadow_map_technique(),
      vsm_technique(),      shadow_volume_technique(), baked_technique(),
      ssao_technique(),     luminance_technique(),     bloom_technique(),
      tonemap_technique(),  visibility_technique(),
  };
  return registry;
}

const TechniqueDecl* find_technique(const std::string& name) {
  for (const TechniqueDecl& t : technique_registry())
    if (t.name == name) return &t;
  return nullptr;
}

std::vector<std::string> technique_names(TechniqueKind kind) {
  std::vector<std::string> out;
  for (const TechniqueDecl& t : technique_registry())
    if (t.kind == kind) out.push_back(t.name);
  return out;
}

const TechniqueDecl& technique_of_kind(const std::string& name, TechniqueKind kind,
                                       const std::string& what) {
  const TechniqueDecl* t = find_technique(name);
  if (t && t->kind == kind) return *t;
  std::string known;
  for (const std::string& n : technique_names(kind)) known += (known.empty() ? "" : ", ") + n;
  throw Error(fmt::format("unknown {} '{}' (known: {})", what, name, known));
}

namespace {

// Bounds of float parameters are declared as floats: print them as such (0.99, not
// 0.9900000095367432).
double bound(const ParamDecl& p, double x) {
  return p.type == ParamType::kInt ? x : std::stod(fmt::format("{}", static_cast<float>(x)));
}

std::string range_of(const ParamDecl& p) {
  switch (p.type) {
    case ParamType::kBool:
      return "";
    case ParamType::kEnum: {
      std::string s;
      for (const std::string& c : p.choices) s += (s.empty() ? "" : "|") + c;
      return s;
    }
    default:
      return fmt::format("[{}, {}]", bound(p, p.min), bound(p, p.max));
  }
}

double shortest(float f) {
  return std::stod(fmt::format("{}", f));
}

const char* change_name(ParamChange c) {
  return c == ParamChange::kPerFrame ? "per-frame" : "structural";
}

}  // namespace

std::string technique_listing() {
  std::string out =
      "Real-time techniques (illum frame / illum view). Choose the frame pipeline with "
      "--technique NAME and the shadow method with --shadows NAME; switch add-ons with "
      "--enable NAME[,NAME] / --disable NAME; set parameters with -p NAME.key=value (or the "
      "short key in brackets). Per-frame parameters change a running frame in place; "
      "structural ones rebuild their technique.\n";
  const std::pair<TechniqueKind, const char*> groups[] = {
      {TechniqueKind::kGlobal, "globals (always on)"},
      {TechniqueKind::kFramePipeline, "frame pipelines (--technique, one of)"},
      {TechniqueKind::kShadowMethod, "shadow methods (--shadows, one of)"},
      {TechniqueKind::kAddOn, "add-ons (--enable / --disable, any number)"},
  };
  for (const auto& [kind, title] : groups) {
    out += fmt::format("\n{}:\n", title);
    for (const TechniqueDecl& t : technique_registry()) {
      if (t.kind != kind) continue;
      std::string state;
      if (kind == TechniqueKind::kAddOn)
        state = t.default_on ? " (on by default)" : " (off by default)";
      if (!t.switch_alias.empty()) state += fmt::format(" [-p {}=true|false]", t.switch_alias);
      out += fmt::format("  {}{}: {}\n", t.name, state, t.summary);
      for (const ParamDecl& p : t.params) {
        const std::string range = range_of(p);
        out += fmt::format("    {}.{}  {}{}{}  default {}  {}{}\n      {}\n", t.name, p.key,
                           type_name(p.type), range.empty() ? "" : " ", range,
                           value_text(p.default_value), change_name(p.change),
                           p.alias.empty() ? "" : fmt::format("  [{}]", p.alias), p.help);
      }
    }
  }
  return out;
}

nlohmann::ordered_json technique_listing_json() {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const TechniqueDecl& t : technique_registry()) {
    nlohmann::ordered_json params = nlohmann::ordered_json::array();
    for (const ParamDecl& p : t.params) {
      nlohmann::ordered_json j = {
          {"name", t.name + "." + p.key}, {"key", p.key}, {"type", type_name(p.type)}};
      std::visit(
          [&](const auto& v) {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<V, Color>)
              j["default"] = {shortest(v.r), shortest(v.g), shortest(v.b)};
            else if constexpr (std::is_same_v<V, float>)
              j["default"] = shortest(v);
            else
              j["default"] = v;
          },
          p.default_value);
      if (p.type == ParamType::kEnum) j["values"] = p.choices;
      if (p.type == ParamType::kInt || p.type == ParamType::kFloat || p.type == ParamType::kColor) {
        j["min"] = bound(p, p.min);
        j["max"] = bound(p, p.max);
      }
      j["change"] = change_name(p.change);
      if (!p.alias.empty()) j["alias"] = p.alias;
      j["help"] = p.help;
      params.push_back(j);
    }
    nlohmann::ordered_json j = {{"name", t.name}, {"kind", kind_name(t.kind)}};
    if (t.kind == TechniqueKind::kAddOn) j["default_on"] = t.default_on;
    if (!t.switch_alias.empty()) j["switch_alias"] = t.switch_alias;
    j["summary"] = t.summary;
    j["params"] = params;
    list.push_back(j);
  }
  return {{"techniques", list}};
}

}  // namespace illum::realtime
