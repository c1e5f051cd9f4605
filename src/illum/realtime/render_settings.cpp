#include "illum/realtime/render_settings.h"

#include <algorithm>
#include <cmath>

#include "illum/core/error.h"
#include "illum/realtime/technique_registry.h"

namespace illum::realtime {

namespace {

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// "NAME.key" → (technique, key); throws Error for a key without a '.'.
std::pair<std::string, std::string> split_key(const std::string& key) {
  const size_t dot = key.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == key.size())
    throw Error(fmt::format("parameter '{}' must look like TECHNIQUE.key", key));
  return {key.substr(0, dot), key.substr(dot + 1)};
}

std::string bounds_text(const ParamDecl& d) {
  return fmt::format("[{}, {}]", d.min, d.max);
}

std::string range_text(const ParamDecl& d) {
  if (d.type == ParamType::kEnum) return "one of " + join(d.choices);
  if (d.type == ParamType::kBool) return "true or false";
  if (d.type == ParamType::kString) return "text";
  return "in " + bounds_text(d);
}

}  // namespace

const ParamDecl& param_decl(const std::string& key) {
  const auto [name, short_key] = split_key(key);
  const TechniqueDecl* t = find_technique(name);
  if (!t) throw Error(fmt::format("parameter '{}': no technique '{}'", key, name));
  const ParamDecl* p = t->param(short_key);
  if (!p) {
    std::vector<std::string> keys;
    for (const ParamDecl& d : t->params) keys.push_back(d.key);
    throw Error(fmt::format("parameter '{}': technique '{}' has no parameter '{}' ({})", key, name,
                            short_key, keys.empty() ? "it has none" : "known: " + join(keys)));
  }
  return *p;
}

ParamValue checked_value(const std::string& key, const ParamDecl& d, const ParamValue& v) {
  auto bad = [&](const std::string& why) {
    return Error(fmt::format("parameter '{}' = {} {}", key, value_text(v), why));
  };
  auto in_range = [&](double x) { return x >= d.min && x <= d.max; };  // NaN fails
  switch (d.type) {
    case ParamType::kBool:
      if (!std::holds_alternative<bool>(v)) throw bad("is not true or false");
      return v;
    case ParamType::kInt:
      if (!std::holds_alternative<int>(v)) throw bad("is not an integer");
      if (!in_range(std::get<int>(v))) throw bad("is outside " + bounds_text(d));
      return v;
    case ParamType::kFloat: {
      float f = 0.0f;
      if (std::holds_alternative<float>(v))
        f = std::get<float>(v);
      else if (std::holds_alternative<int>(v))
        f = static_cast<float>(std::get<int>(v));
      else
        throw bad("is not a number");
      if (!std::isfinite(f) || !in_range(f)) throw bad("is outside " + bounds_text(d));
      return f;
    }
    case ParamType::kColor: {
      if (!std::holds_alternative<Color>(v)) throw bad("is not a colour [r, g, b]");
      const Color c = std::get<Color>(v);
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(c[k]) || !in_range(c[k]))
          throw bad("has a component outside " + bounds_text(d));
      return v;
    }
    case ParamType::kEnum:
      if (!std::holds_alternative<std::string>(v) ||
          std::find(d.choices.begin(), d.choices.end(), std::get<std::string>(v)) ==
              d.choices.end())
        throw bad("is not " + range_text(d));
      return v;
    case ParamType::kString:
      if (!std::holds_alternative<std::string>(v)) throw bad("is not text");
      return v;
  }
  throw InternalError("unhandled parameter type");
}

RenderSettings::RenderSettings() {
  for (const TechniqueDecl& t : technique_registry())
    if (t.kind == TechniqueKind::kAddOn && t.default_on) enable(t.name);
}

void RenderSettings::set(const std::string& key, const ParamValue& value) {
  values_[key] = checked_value(key, param_decl(key), value);
}

const ParamValue& RenderSettings::value(const std::string& key) const {
  const auto it = values_.find(key);
  if (it != values_.end()) return it->second;
  return param_decl(key).default_value;
}

namespace {

// A JSON value from the command line as the declared type.
ParamValue from_json(const std::string& key, const ParamDecl& d, const nlohmann::json& j,
                     const std::string& origin) {
  auto bad = [&] {
    return Error(fmt::format("{} {}={}: {} is a {} ({})", origin, key, j.dump(), key,
                             type_name(d.type), range_text(d)));
  };
  switch (d.type) {
    case ParamType::kBool:
      if (!j.is_boolean()) throw bad();
      return j.get<bool>();
    case ParamType::kInt:
      if (!j.is_number_integer() || j.get<long long>() < INT32_MIN ||
          j.get<long long>() > INT32_MAX)
        throw bad();
      return static_cast<int>(j.get<long long>());
    case ParamType::kFloat:
      if (!j.is_number()) throw bad();
      return j.get<float>();
    case ParamType::kColor:
      if (!j.is_array() || j.size() != 3 ||
          !std::all_of(j.begin(), j.end(), [](const nlohmann::json& x) { return x.is_number(); }))
        throw bad();
      return Color(j[0].get<float>(), j[1].get<float>(), j[2].get<float>());
    case ParamType::kEnum:
    case ParamType::kString:
      if (!j.is_string()) throw bad();
      return j.get<std::string>();
  }
  throw InternalError("unhandled parameter type");
}

bool positive(const ParamValue& v) {
  if (std::holds_alternative<bool>(v)) return std::get<bool>(v);
  if (std::holds_alternative<int>(v)) return std::get<int>(v) > 0;
  if (std::holds_alternative<float>(v)) return std::get<float>(v) > 0.0f;
  if (std::holds_alternative<std::string>(v)) return !std::get<std::string>(v).empty();
  return true;
}

}  // namespace

void RenderSettings::set_param(const std::string& key, const nlohmann::json& value,
                               const std::string& origin) {
  auto checked = [&](const std::string& full, const ParamDecl& d) {
    try {
      return checked_value(full, d, from_json(full, d, value, origin));
    } catch (const Error& e) {
      throw Error(fmt::format("{} {}: {}", origin, key, e.what()));
    }
  };
  if (key.find('.') != std::string::npos) {
    const ParamDecl* d = nullptr;
    try {
      d = &param_decl(key);
    } catch (const Error& e) {
      throw Error(fmt::format("{} {}: {}", origin, key, e.what()));
    }
    values_[key] = checked(key, *d);
    if (d->key_switches) {
      const std::string name = split_key(key).first;
      positive(values_[key]) ? enable(name) : disable(name);
    }
    return;
  }
  bool known = false;
  for (const TechniqueDecl& t : technique_registry()) {
    if (!t.switch_alias.empty() && t.switch_alias == key) {
      if (!value.is_boolean())
        throw Error(fmt::format("{} {}={}: {} is true or false (it switches '{}')", origin, key,
                                value.dump(), key, t.name));
      value.get<bool>() ? enable(t.name) : disable(t.name);
      known = true;
    }
    for (const ParamDecl& d : t.params) {
      if (d.alias != key) continue;
      const std::string full = t.name + "." + d.key;
      const ParamValue v = checked(full, d);
      values_[full] = v;
      if (d.alias_switches) positive(v) ? enable(t.name) : disable(t.name);
      known = true;
    }
  }
  if (!known)
    throw Error(
        fmt::format("{} {}: unknown parameter (use TECHNIQUE.key; `illum frame --list` lists them)",
                    origin, key));
}

void RenderSettings::enable(const std::string& name) {
  const TechniqueDecl* t = find_technique(name);
  if (!t)
    throw Error(fmt::format("--enable {}: no technique '{}' (add-ons: {})", name, name,
                            join(technique_names(TechniqueKind::kAddOn))));
  if (t->kind == TechniqueKind::kFramePipeline)
    throw Error(
        fmt::format("--enable {}: '{}' is a frame pipeline, chosen with --technique", name, name));
  if (t->kind == TechniqueKind::kShadowMethod)
    throw Error(
        fmt::format("--enable {}: '{}' is a shadow method, chosen with --shadows", name, name));
  if (t->kind == TechniqueKind::kGlobal)
    throw Error(fmt::format("--enable {}: '{}' is always on", name, name));
  add_ons.insert(name);
  for (const std::string& d : t->dependencies) enable(d);  // the registry has no cycles
}

std::string RenderSettings::needed_by(const std::string& name) const {
  for (const std::string& a : add_ons) {
    const TechniqueDecl* t = find_technique(a);
    if (t && a != name &&
        std::find(t->dependencies.begin(), t->dependencies.end(), name) != t->dependencies.end())
      return a;
  }
  return "";
}

void RenderSettings::disable(const std::string& name) {
  const TechniqueDecl* t = find_technique(name);
  if (!t || t->kind != TechniqueKind::kAddOn) {
    try {
      enable(name);  // the same messages
    } catch (const Error& e) {
      std::string m = e.what();
      m.replace(0, std::string("--enable").size(), "--disable");
      throw Error(m);
    }
  }
  const std::string needer = needed_by(name);
  if (active(name) && !needer.empty())
    throw Error(
        fmt::format("--disable {0}: '{1}' needs '{0}' (switch '{1}' off first)", name, needer));
  add_ons.erase(name);
}

bool RenderSettings::active(const std::string& name) const {
  const TechniqueDecl* t = find_technique(name);
  if (!t) return false;
  switch (t->kind) {
    case TechniqueKind::kGlobal:
      return true;
    case TechniqueKind::kFramePipeline:
      return pipeline == name;
    case TechniqueKind::kShadowMethod:
      return shadows == name;
    case TechniqueKind::kAddOn:
      return add_ons.count(name) > 0;
  }
  return false;
}

std::vector<std::string> RenderSettings::active_techniques() const {
  std::vector<std::string> out;
  for (const TechniqueDecl& t : technique_registry())
    if (active(t.name)) out.push_back(t.name);
  return out;
}

void RenderSettings::check() const {
  for (const auto& [name, value] : {std::pair{"width", width}, std::pair{"height", height}})
    if (value < 1 || value > 16384)
      throw Error(fmt::format("renderer option '{}' = {} is outside [1, 16384]", name, value));
  technique_of_kind(pipeline, TechniqueKind::kFramePipeline, "frame pipeline");
  technique_of_kind(shadows, TechniqueKind::kShadowMethod, "shadow method");
  for (const std::string& a : add_ons) {
    const TechniqueDecl& t = technique_of_kind(a, TechniqueKind::kAddOn, "add-on");
    for (const std::string& d : t.dependencies)
      if (!add_ons.count(d)) throw Error(fmt::format("add-on '{}' needs '{}', which is off", a, d));
  }
}

}  // namespace illum::realtime
