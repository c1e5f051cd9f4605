#include "illum/core/params.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "illum/core/json_input.h"

namespace illum {

Params::Params(nlohmann::json object, std::string origin, std::string path) {
  if (!object.is_object())
    throw Error(
        fmt::format("{}: {} must be a JSON object", origin, path.empty() ? "top level" : path));
  state_->json = std::move(object);
  state_->origin = std::move(origin);
  state_->path = std::move(path);
}

Params Params::from_file(const std::string& json_path) {
  // Nesting is bounded before parsing: Params copies sub-objects, which recurses per level.
  return Params(read_json_file(json_path, /*allow_comments=*/true), json_path);
}

bool Params::has(const std::string& key) const {
  state_->asked.insert(key);
  return state_->json.contains(key);
}

std::string Params::where(const std::string& key) const {
  return fmt::format("{}: '{}{}'", state_->origin, state_->path.empty() ? "" : state_->path + ".",
                     key);
}

const nlohmann::json& Params::at(const std::string& key) const {
  state_->asked.insert(key);
  auto it = state_->json.find(key);
  if (it == state_->json.end()) throw Error(fmt::format("{} is required but missing", where(key)));
  state_->used.insert(key);
  return *it;
}

void Params::mark_used(const std::string& key) const {
  state_->used.insert(key);
}

namespace {
float finite_number(const nlohmann::json& v, const std::string& where) {
  if (!v.is_number()) throw Error(fmt::format("{} must be a number", where));
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw Error(fmt::format("{} must be finite", where));
  return static_cast<float>(d);
}
template <int N>
glm::vec<N, float> vector_of(const nlohmann::json& v, const std::string& where) {
  if (!v.is_array() || v.size() != N)
    throw Error(fmt::format("{} must be an array of {} numbers", where, N));
  glm::vec<N, float> out;
  for (int i = 0; i < N; ++i) out[i] = finite_number(v[i], where);
  return out;
}
}  // namespace

template <>
bool Params::get<bool>(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_boolean()) throw Error(fmt::format("{} must be true or false", where(key)));
  return v.get<bool>();
}
template <>
int Params::get<int>(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_number_integer()) throw Error(fmt::format("{} must be an integer", where(key)));
  const auto i = v.get<long long>();
  if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
    throw Error(fmt::format("{} is out of range", where(key)));
  return static_cast<int>(i);
}
template <>
float Params::get<float>(const std::string& key) const {
  return finite_number(at(key), where(key));
}
template <>
std::string Params::get<std::string>(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_string()) throw Error(fmt::format("{} must be a string", where(key)));
  return v.get<std::string>();
}
template <>
vec2 Params::get<vec2>(const std::string& key) const {
  return vector_of<2>(at(key), where(key));
}
template <>
vec3 Params::get<vec3>(const std::string& key) const {
  return vector_of<3>(at(key), where(key));
}
template <>
std::vector<float> Params::get<std::vector<float>>(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_array()) throw Error(fmt::format("{} must be an array of numbers", where(key)));
  std::vector<float> out;
  for (const auto& e : v) out.push_back(finite_number(e, where(key)));
  return out;
}
template <>
std::vector<std::string> Params::get<std::vector<std::string>>(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_array()) throw Error(fmt::format("{} must be an array of strings", where(key)));
  std::vector<std::string> out;
  for (const auto& e : v) {
    if (!e.is_string()) throw Error(fmt::format("{} must be an array of strings", where(key)));
    out.push_back(e.get<std::string>());
  }
  return out;
}

float Params::get_float_in(const std::string& key, float fallback, float lo, float hi) const {
  const float v = get<float>(key, fallback);
  if (v < lo || v > hi)
    throw Error(fmt::format("{} = {} is outside [{}, {}]", where(key), v, lo, hi));
  return v;
}
int Params::get_int_in(const std::string& key, int fallback, int lo, int hi) const {
  const int v = get<int>(key, fallback);
  if (v < lo || v > hi)
    throw Error(fmt::format("{} = {} is outside [{}, {}]", where(key), v, lo, hi));
  return v;
}

uint64_t Params::get_seed(const std::string& key, uint64_t fallback) const {
  if (!has(key)) return fallback;
  const nlohmann::json& seed = at(key);
  if (!(seed.is_number_unsigned() || (seed.is_number_integer() && seed.get<int64_t>() >= 0)))
    throw Error(fmt::format("{} must be a non-negative integer", where(key)));
  return seed.get<uint64_t>();
}

Params Params::child(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_object()) throw Error(fmt::format("{} must be an object", where(key)));
  Params p(v, state_->origin, state_->path.empty() ? key : state_->path + "." + key);
  state_->handed_out.push_back(p);
  return p;
}

std::vector<Params> Params::children(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_array()) throw Error(fmt::format("{} must be an array of objects", where(key)));
  std::vector<Params> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string sub =
        fmt::format("{}{}[{}]", state_->path.empty() ? "" : state_->path + ".", key, i);
    if (!v[i].is_object())
      throw Error(fmt::format("{}: '{}' must be an object", state_->origin, sub));
    Params p(v[i], state_->origin, sub);
    state_->handed_out.push_back(p);
    out.push_back(p);
  }
  return out;
}

void Params::check_all_used() const {
  for (const auto& [key, value] : state_->json.items()) {
    if (state_->used.count(key)) continue;
    std::vector<std::string> known;
    for (const std::string& k : state_->asked)
      if (!state_->unlisted.count(k) && k != key) known.push_back(k);
    if (known.empty()) throw Error(fmt::format("{} is not a known key", where(key)));
    const std::string near = nearest_name(key, known);
    throw Error(fmt::format("{} is not a known key{} (known: {})", where(key),
                            near.empty() ? "" : fmt::format("; did you mean '{}'?", near),
                            fmt::join(known, ", ")));
  }
  for (const auto& c : state_->handed_out) c.check_all_used();
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
  // Past a third of the name's length the "suggestion" is mostly another word.
  const size_t limit = std::max<size_t>(2, name.size() / 3);
  std::string best;
  size_t best_distance = limit + 1;
  for (const std::string& c : candidates) {
    const size_t d = edit_distance(name, c);
    if (d < best_distance) best = c, best_distance = d;
  }
  return best;
}

}  // namespace illum
