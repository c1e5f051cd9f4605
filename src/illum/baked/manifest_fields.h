// The typed reading of a bake folder's manifest (lightmap.json, prt.json, probes.json): every
// field is checked for presence, type and range before anything uses it, and every refusal is
// one illum::Error line "<manifest>: '<key>' must be …, not <value>" naming the field (a key
// of a nested object as 'grid.spacing'). A manifest is user input like any file: a count that
// sizes an allocation is bounded here, and checked against the bytes of its data file by the
// reader that allocates.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

#include "illum/atlas/atlas.h"

namespace illum::baked {

// Bounds of the fields every bake manifest records. Triangles: Embree numbers primitives in
// 32 bits. Atlas size and charts: the atlas file's own limits (atlas/atlas_file.cpp). Texel
// size: a thousand kilometres per texel is past any scene; the bound keeps the value finite
// in float.
inline constexpr uint64_t kMaxManifestTriangles = uint64_t{1} << 32;
inline constexpr uint64_t kMaxManifestAtlasSize = 65536;
inline constexpr uint64_t kMaxManifestCharts = (uint64_t{1} << 31) - 1;
inline constexpr double kMaxManifestTexelSize = 1e6;

class ManifestFields {
 public:
  // `where` names the manifest file in messages; `prefix` is the key path of a nested object
  // ("grid."). Throws unless `json` is an object.
  ManifestFields(const nlohmann::json& json, std::string where, std::string prefix = "");

  [[noreturn]] void fail(const std::string& what) const;
  // 'format' must be `format` and 'version' `version`: "'version' is 2, but this illum reads
  // illum-prt version 1".
  void expect_format(const char* format, uint64_t version) const;
  // A count recorded twice (the manifest and the atlas or data file): "'width' is 16, but
  // the atlas's is 8".
  void expect_same(const char* key, uint64_t value, uint64_t actual, const char* source) const;
  bool has(const char* key) const;
  // The value, or Error "'key' is missing".
  const nlohmann::json& at(const char* key) const;
  // A nested object, its keys named "key.sub" in messages.
  ManifestFields object(const char* key) const;
  std::string string(const char* key) const;
  // One of `choices`: "'key' must be one of a, b, c, not 'x'".
  std::string one_of(const char* key, std::initializer_list<const char*> choices) const;
  // An integer in [min, max] (1.0, "1", -1 and 1e12 past `max` are refused).
  uint64_t integer(const char* key, uint64_t min, uint64_t max) const;
  // A finite number in [min, max]; with `positive`, above 0 as well.
  double number(const char* key, double min, double max, bool positive = false) const;
  // A plain file name of the folder: no folder part, not "." or "..".
  std::string file_name(const char* key) const;
  std::string file_name(const char* key, const nlohmann::json& value) const;
  // 16 lowercase hex digits (scene/geometry_hash.h).
  std::string scene_hash(const char* key) const;
  // An object (a bake's free-form record of its settings).
  const nlohmann::json& free_object(const char* key) const;

  // The key as messages name it ("grid.spacing").
  std::string name(const char* key) const { return prefix_ + key; }
  // A value for a message: its JSON, cut to 40 characters.
  static std::string shown(const nlohmann::json& value);
  const nlohmann::json& json() const { return *json_; }
  const std::string& where() const { return where_; }

 private:
  const nlohmann::json* json_;
  std::string where_, prefix_;
};

// The atlas file the manifest names ('atlas'), with the manifest's 'width', 'height',
// 'charts' and 'texel_size' checked first by type and range, then against the atlas: a
// manifest beside another folder's atlas.bin is refused, not shown with the wrong
// coordinates.
atlas::Atlas read_manifest_atlas(const ManifestFields& manifest,
                                 const std::filesystem::path& folder);

}  // namespace illum::baked
