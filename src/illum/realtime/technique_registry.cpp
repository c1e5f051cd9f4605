#include "illum/realtime/technique_registry.h"

#include <algorithm>
#include <functional>

#include "illum/core/error.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

TechniqueList& registry_list() {
  // The one list of techniques. Within a kind, the order is the frame's: add-ons run in
  // this order (tone mapping, then the debug view, last: it shows what the others declare).
  static TechniqueList registry = [] {
    TechniqueList list = {
        lighting_globals(),       scene_draw_globals(),      forward_technique(),
        deferred_technique(),     no_shadows_technique(),    shadow_map_technique(),
        vsm_technique(),          shadow_volume_technique(), baked_technique(),
        ssao_technique(),         luminance_technique(),     bloom_technique(),
        tonemap_technique(),      visibility_technique(),    rsm_technique(),
        light_volume_technique(), lpv_technique(),           vpl_technique(),
        debug_show_technique(),
    };
    check_declarations(list);
    return list;
  }();
  return registry;
}

}  // namespace

const TechniqueList& technique_registry() {
  return registry_list();
}

void check_declarations(const TechniqueList& list) {
  auto find = [&](const std::string& name) -> const TechniqueDecl* {
    for (const TechniqueDecl& t : list)
      if (t.name == name) return &t;
    return nullptr;
  };
  for (const TechniqueDecl& t : list) {
    ILLUM_CHECK(t.name.find('.') == std::string::npos && !t.name.empty(),
                "technique '{}': a name has no '.' (keys are NAME.key)", t.name);
    ILLUM_CHECK(find(t.name) == &t, "technique '{}' is declared twice", t.name);
    for (const std::string& d : t.dependencies) {
      const TechniqueDecl* dep = find(d);
      ILLUM_CHECK(dep, "technique '{}' needs '{}', which is not declared", t.name, d);
      ILLUM_CHECK(dep->kind == TechniqueKind::kAddOn && t.kind == TechniqueKind::kAddOn,
                  "technique '{}' ({}) needs '{}' ({}): only add-ons need add-ons", t.name,
                  kind_name(t.kind), d, kind_name(dep->kind));
    }
  }
  // Depth-first from each technique along its dependencies; meeting a technique still on
  // the path is a cycle, reported as the path.
  std::vector<std::string> path;
  std::function<void(const TechniqueDecl&)> visit = [&](const TechniqueDecl& t) {
    const auto on_path = std::find(path.begin(), path.end(), t.name);
    if (on_path != path.end()) {
      std::string cycle;
      for (auto it = on_path; it != path.end(); ++it) cycle += *it + " -> ";
      throw InternalError(
          fmt::format("techniques need each other in a cycle: {}{}", cycle, t.name));
    }
    path.push_back(t.name);
    for (const std::string& d : t.dependencies) visit(*find(d));
    path.pop_back();
  };
  for (const TechniqueDecl& t : list) visit(t);
}

TechniqueRegistration::TechniqueRegistration(TechniqueDecl decl) : name_(decl.name) {
  TechniqueList& list = registry_list();
  list.push_back(std::move(decl));
  try {
    check_declarations(list);
  } catch (...) {
    list.pop_back();
    throw;
  }
}

TechniqueRegistration::~TechniqueRegistration() {
  TechniqueList& list = registry_list();
  if (!list.empty() && list.back().name == name_) list.pop_back();
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
    case ParamType::kString:
      return "text";
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
      if (!t.dependencies.empty()) {
        std::string needs;
        for (const std::string& d : t.dependencies) needs += (needs.empty() ? "" : ", ") + d;
        out += fmt::format("    needs: {} (switched on with it)\n", needs);
      }
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
    j["dependencies"] = t.dependencies;
    j["summary"] = t.summary;
    j["params"] = params;
    list.push_back(j);
  }
  return {{"techniques", list}};
}

}  // namespace illum::realtime
