// A typed parameter dictionary that remembers which keys were read. After the reader has
// taken what it knows, check_all_used() turns every unknown or unused key into an Error
// naming the file (or CLI option group) and the key, so typos never pass silently.
// Defaults live in the code that reads them: get(key, default).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/core/error.h"
#include "illum/core/math.h"

namespace illum {

class Params {
 public:
  Params() = default;
  // `origin` names where the values came from ("scene.illum.json", "--option"), and
  // `path` where in it ("lights[2]"); both appear in every error message.
  Params(nlohmann::json object, std::string origin, std::string path = "");

  // Reads a JSON file (comments allowed) through read_json_file (core/json_input.h): nesting
  // past kMaxJsonDepth, a syntax error or a number beyond a double is an Error naming the file.
  static Params from_file(const std::string& json_path);

  bool has(const std::string& key) const;
  const std::string& origin() const { return state_->origin; }
  std::string where(const std::string& key) const;  // "file: lights[2].flux"

  // Typed getters: throw illum::Error naming origin and key on a type mismatch, a
  // non-finite number, or (for the required form) a missing key.
  template <typename T>
  T get(const std::string& key) const;
  template <typename T>
  T get(const std::string& key, const T& fallback) const {
    return has(key) ? get<T>(key) : fallback;
  }
  // A numeric value that must lie in [lo, hi].
  float get_float_in(const std::string& key, float fallback, float lo, float hi) const;
  int get_int_in(const std::string& key, int fallback, int lo, int hi) const;
  // A random seed: any non-negative integer up to 2⁶⁴ − 1 (an Error otherwise).
  uint64_t get_seed(const std::string& key, uint64_t fallback) const;

  // Nested objects and arrays of objects, with their own read tracking.
  Params child(const std::string& key) const;
  std::vector<Params> children(const std::string& key) const;

  // Marks a key as consumed without reading it through this dictionary.
  void mark_used(const std::string& key) const;
  // Throws Error for the first key never read, naming it, the nearest key the readers asked
  // for ("did you mean 'max_depth'?") and every key they asked for but the unlisted ones;
  // recurses into children that were handed out.
  void check_all_used() const;
  // Keys left out of that list: those a dedicated option sets (and refuses here).
  void unlist(std::set<std::string> keys) const { state_->unlisted = std::move(keys); }
  // Whether a reader took `key` (a value the reader has no use for was given).
  bool was_read(const std::string& key) const { return state_->used.count(key) > 0; }

  const nlohmann::json& raw() const { return state_->json; }

 private:
  // Copies of a Params share one state, so reads through a copy count for the original.
  struct State {
    nlohmann::json json = nlohmann::json::object();
    std::string origin = "parameters";
    std::string path;
    std::set<std::string> used;
    std::set<std::string> asked;  // every key a reader looked for: the valid ones
    std::set<std::string> unlisted;
    std::vector<Params> handed_out;
  };
  const nlohmann::json& at(const std::string& key) const;
  std::shared_ptr<State> state_ = std::make_shared<State>();
};

// Levenshtein distance, and the candidate nearest to `name` within a third of its length
// (at least 2 edits), or "": the "did you mean" of unknown keys and options.
size_t edit_distance(const std::string& a, const std::string& b);
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates);

template <>
bool Params::get<bool>(const std::string& key) const;
template <>
int Params::get<int>(const std::string& key) const;
template <>
float Params::get<float>(const std::string& key) const;
template <>
std::string Params::get<std::string>(const std::string& key) const;
template <>
vec2 Params::get<vec2>(const std::string& key) const;
template <>
vec3 Params::get<vec3>(const std::string& key) const;
template <>
std::vector<float> Params::get<std::vector<float>>(const std::string& key) const;
template <>
std::vector<std::string> Params::get<std::vector<std::string>>(const std::string& key) const;

}  // namespace illum
