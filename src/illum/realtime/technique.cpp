#include "illum/realtime/technique.h"

#include "illum/core/error.h"

namespace illum::realtime {

const char* kind_name(TechniqueKind kind) {
  switch (kind) {
    case TechniqueKind::kGlobal:
      return "globals";
    case TechniqueKind::kFramePipeline:
      return "frame pipeline";
    case TechniqueKind::kShadowMethod:
      return "shadow method";
    case TechniqueKind::kAddOn:
      return "add-on";
  }
  return "?";
}

const char* type_name(ParamType type) {
  switch (type) {
    case ParamType::kBool:
      return "bool";
    case ParamType::kInt:
      return "int";
    case ParamType::kFloat:
      return "float";
    case ParamType::kColor:
      return "color";
    case ParamType::kEnum:
      return "enum";
    case ParamType::kString:
      return "string";
  }
  return "?";
}

std::string value_text(const ParamValue& v) {
  if (std::holds_alternative<bool>(v)) return std::get<bool>(v) ? "true" : "false";
  if (std::holds_alternative<int>(v)) return std::to_string(std::get<int>(v));
  if (std::holds_alternative<float>(v)) return fmt::format("{}", std::get<float>(v));
  if (std::holds_alternative<Color>(v)) {
    const Color c = std::get<Color>(v);
    return fmt::format("[{}, {}, {}]", c.r, c.g, c.b);
  }
  return std::get<std::string>(v);
}

ParamDecl ParamDecl::structural() const {
  ParamDecl d = *this;
  d.change = ParamChange::kStructural;
  return d;
}

ParamDecl ParamDecl::aka(const std::string& short_key, bool switches) const {
  ParamDecl d = *this;
  d.alias = short_key;
  d.alias_switches = switches;
  return d;
}

ParamDecl ParamDecl::slider(UiHint hint, double lo, double hi) const {
  ParamDecl d = *this;
  d.ui = hint;
  d.ui_min = lo;
  d.ui_max = hi;
  return d;
}

ParamDecl bool_param(const std::string& key, bool fallback, const std::string& help) {
  ParamDecl d;
  d.key = key;
  d.type = ParamType::kBool;
  d.default_value = fallback;
  d.help = help;
  return d;
}

ParamDecl int_param(const std::string& key, int fallback, int lo, int hi, const std::string& help) {
  ParamDecl d;
  d.key = key;
  d.type = ParamType::kInt;
  d.default_value = fallback;
  d.min = lo;
  d.max = hi;
  d.help = help;
  return d;
}

ParamDecl float_param(const std::string& key, float fallback, float lo, float hi,
                      const std::string& help) {
  ParamDecl d;
  d.key = key;
  d.type = ParamType::kFloat;
  d.default_value = fallback;
  d.min = lo;
  d.max = hi;
  d.help = help;
  return d;
}

ParamDecl color_param(const std::string& key, Color fallback, float lo, float hi,
                      const std::string& help) {
  ParamDecl d = float_param(key, 0.0f, lo, hi, help);
  d.type = ParamType::kColor;
  d.default_value = fallback;
  return d;
}

ParamDecl enum_param(const std::string& key, const std::string& fallback,
                     std::vector<std::string> choices, const std::string& help) {
  ParamDecl d;
  d.key = key;
  d.type = ParamType::kEnum;
  d.default_value = fallback;
  d.choices = std::move(choices);
  d.help = help;
  ILLUM_CHECK(std::find(d.choices.begin(), d.choices.end(), fallback) != d.choices.end(),
              "parameter '{}': default '{}' is not one of its values", key, fallback);
  return d;
}

ParamDecl string_param(const std::string& key, const std::string& fallback,
                       const std::string& help) {
  ParamDecl d;
  d.key = key;
  d.type = ParamType::kString;
  d.default_value = fallback;
  d.help = help;
  return d;
}

const ParamDecl* TechniqueDecl::param(const std::string& key) const {
  for (const ParamDecl& p : params)
    if (p.key == key) return &p;
  return nullptr;
}

}  // namespace illum::realtime
