#include "illum/baked/manifest_fields.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "illum/core/error.h"

namespace illum::baked {

ManifestFields::ManifestFields(const nlohmann::json& json, std::string where, std::string prefix)
    : json_(&json), where_(std::move(where)), prefix_(std::move(prefix)) {
  if (!json.is_object()) {
    if (prefix_.empty()) fail("the manifest must be a JSON object");
    fail(fmt::format("'{}' must be an object, not {}",
                     prefix_.substr(0, prefix_.empty() ? 0 : prefix_.size() - 1), shown(json)));
  }
}

void ManifestFields::fail(const std::string& what) const {
  throw Error(fmt::format("{}: {}", where_, what));
}

void ManifestFields::expect_format(const char* format, uint64_t version) const {
  const std::string found = string("format");
  if (found != format)
    fail(fmt::format("'format' is {}, not \"{}\"", shown(nlohmann::json(found)), format));
  const uint64_t v = integer("version", 0, uint64_t{1} << 30);
  if (v != version)
    fail(fmt::format("'version' is {}, but this illum reads {} version {}", v, format, version));
}

void ManifestFields::expect_same(const char* key, uint64_t value, uint64_t actual,
                                 const char* source) const {
  if (value != actual)
    fail(fmt::format("'{}' is {}, but {} says {}", name(key), value, source, actual));
}

std::string ManifestFields::shown(const nlohmann::json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

bool ManifestFields::has(const char* key) const {
  return json_->contains(key);
}

const nlohmann::json& ManifestFields::at(const char* key) const {
  const auto it = json_->find(key);
  if (it == json_->end()) fail(fmt::format("'{}' is missing", name(key)));
  return *it;
}

ManifestFields ManifestFields::object(const char* key) const {
  return ManifestFields(at(key), where_, name(key) + ".");
}

std::string ManifestFields::string(const char* key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_string()) fail(fmt::format("'{}' must be a string, not {}", name(key), shown(v)));
  return v.get<std::string>();
}

std::string ManifestFields::one_of(const char* key,
                                   std::initializer_list<const char*> choices) const {
  const std::string value = string(key);
  std::string list;
  for (const char* c : choices) {
    if (value == c) return value;
    list += (list.empty() ? "" : ", ") + std::string(c);
  }
  fail(fmt::format("'{}' must be one of {}, not {}", name(key), list, shown(value)));
}

uint64_t ManifestFields::integer(const char* key, uint64_t min, uint64_t max) const {
  const nlohmann::json& v = at(key);
  // Unsigned or a non-negative signed integer; never a float, even 1.0: the writers write
  // integers, so a float means the file was edited or corrupted.
  const bool whole = v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0);
  if (!whole || v.get<uint64_t>() < min || v.get<uint64_t>() > max)
    fail(fmt::format("'{}' must be an integer in [{}, {}], not {}", name(key), min, max, shown(v)));
  return v.get<uint64_t>();
}

double ManifestFields::number(const char* key, double min, double max, bool positive) const {
  const nlohmann::json& v = at(key);
  const double d = v.is_number() ? v.get<double>() : std::nan("");
  if (!std::isfinite(d) || d < min || d > max || (positive && !(d > 0.0)))
    fail(fmt::format("'{}' must be a {}number in {}{}, {}], not {}", name(key),
                     positive ? "positive " : "", positive && min <= 0.0 ? "(" : "[",
                     positive && min <= 0.0 ? 0.0 : min, max, shown(v)));
  return d;
}

std::string ManifestFields::file_name(const char* key) const {
  return file_name(key, at(key));
}

std::string ManifestFields::file_name(const char* key, const nlohmann::json& v) const {
  if (!v.is_string()) fail(fmt::format("'{}' must be a file name, not {}", name(key), shown(v)));
  const std::string file = v.get<std::string>();
  const std::filesystem::path p(file);
  if (file.empty() || p.has_parent_path() || p.is_absolute() || file == "." || file == ".." ||
      file.find('\\') != std::string::npos)
    fail(fmt::format("'{}': '{}' must be a file in the folder", name(key), file.substr(0, 40)));
  return file;
}

std::string ManifestFields::scene_hash(const char* key) const {
  const std::string hash = string(key);
  if (hash.size() != 16 || hash.find_first_not_of("0123456789abcdef") != std::string::npos)
    fail(fmt::format("'{}' must be 16 lowercase hex digits, not {}", name(key),
                     shown(nlohmann::json(hash))));
  return hash;
}

const nlohmann::json& ManifestFields::free_object(const char* key) const {
  const nlohmann::json& v = at(key);
  if (!v.is_object()) fail(fmt::format("'{}' must be an object, not {}", name(key), shown(v)));
  return v;
}

atlas::Atlas read_manifest_atlas(const ManifestFields& manifest,
                                 const std::filesystem::path& folder) {
  const uint64_t width = manifest.integer("width", 1, kMaxManifestAtlasSize);
  const uint64_t height = manifest.integer("height", 1, kMaxManifestAtlasSize);
  const uint64_t charts = manifest.integer("charts", 0, kMaxManifestCharts);
  const double texel_size = manifest.number("texel_size", 0.0, kMaxManifestTexelSize, true);
  atlas::Atlas atlas = atlas::load_atlas(folder / manifest.file_name("atlas"));
  manifest.expect_same("width", width, uint64_t(atlas.width), "the atlas");
  manifest.expect_same("height", height, uint64_t(atlas.height), "the atlas");
  manifest.expect_same("charts", charts, uint64_t(atlas.chart_count), "the atlas");
  if (float(texel_size) != atlas.texel_size)
    manifest.fail(fmt::format(
        "'texel_size' is {}, but the atlas says {} (an atlas.bin of another bake); bake it again",
        texel_size, atlas.texel_size));
  return atlas;
}

}  // namespace illum::baked
