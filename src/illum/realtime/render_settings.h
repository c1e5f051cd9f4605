// What a real-time frame is made of: its size, the frame pipeline and shadow method (one of
// each, by name), the add-ons switched on, and the parameter values that differ from the
// declared defaults, keyed "NAME.key" (technique.h). Every value is checked against its
// declaration when it is set, so a RenderSettings never holds an unknown key, a value of the
// wrong type or one outside its range.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/realtime/technique.h"

namespace illum::realtime {

struct RenderSettings {
  int width = 512;
  int height = 512;
  std::string pipeline = "forward";
  std::string shadows = "map";
  std::set<std::string> add_ons;  // switched on; starts with the declared defaults

  RenderSettings();

  // Sets "NAME.key"; throws Error naming the key for an unknown technique or key, a value
  // of another type (an int is taken for a float) or one outside the declared range or
  // values.
  void set(const std::string& key, const ParamValue& value);
  // The value of "NAME.key": the one set, or the declared default.
  const ParamValue& value(const std::string& key) const;
  template <typename T>
  T get(const std::string& key) const {
    return std::get<T>(value(key));
  }
  // The values set explicitly.
  const std::map<std::string, ParamValue>& values() const { return values_; }

  // A `-p` item: "NAME.key" or a short alias (several declarations may share one, and
  // alias_switches aliases also switch their technique; a technique's switch_alias switches
  // it), with a JSON value as key_values_to_json made it. Throws Error naming `origin` and
  // the key.
  void set_param(const std::string& key, const nlohmann::json& value,
                 const std::string& origin = "--param");

  // Add-ons: throws Error for an unknown name, or one that is a frame pipeline or shadow
  // method (those are chosen by name: pipeline, shadows). enable() switches on what the
  // add-on needs (TechniqueDecl::dependencies, transitively); disable() refuses, with one
  // line naming both, an add-on another one switched on needs.
  void enable(const std::string& name);
  void disable(const std::string& name);
  // An add-on switched on that needs `name`, or "".
  std::string needed_by(const std::string& name) const;
  // Whether `name` takes part in the frame: the globals, the chosen pipeline and shadow
  // method, and the add-ons switched on.
  bool active(const std::string& name) const;
  // The active techniques in frame order (registry order).
  std::vector<std::string> active_techniques() const;

  // The size, pipeline, shadow method, add-on names and that every add-on on has what it
  // needs; throws Error naming what is wrong.
  void check() const;

  bool operator==(const RenderSettings& other) const = default;

 private:
  std::map<std::string, ParamValue> values_;
};

// The declaration of "NAME.key", or throws Error naming it.
const ParamDecl& param_decl(const std::string& key);
// `value` as the declared type (an int for a float is converted); throws Error naming `key`
// for another type or a value outside the declared range or values.
ParamValue checked_value(const std::string& key, const ParamDecl& decl, const ParamValue& value);

}  // namespace illum::realtime
