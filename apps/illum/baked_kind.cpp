#include "baked_kind.h"

#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "illum/core/error.h"

namespace illum::cli {

namespace fs = std::filesystem;

namespace {

constexpr BakedKindInfo kBakedKinds[] = {
    {BakedKind::kLightmap, "light-map", "lightmap.json"},
    {BakedKind::kPrt, "PRT", "prt.json"},
    {BakedKind::kProbes, "probes", "probes.json"},
};

std::string known_manifests() {
  std::string names;
  for (const BakedKindInfo& k : kBakedKinds)
    names += fmt::format("{}{} ({})", names.empty() ? "" : ", ", k.manifest, k.name);
  return names;
}

// The "format" a JSON file in the folder declares, or "" (a hint for a folder of a kind this
// illum does not know, e.g. one written by a newer illum).
std::string declared_format(const fs::path& folder) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
    if (e.path().extension() != ".json") continue;
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(e.path()), nullptr, false);
    if (j.is_object() && j.contains("format") && j.at("format").is_string())
      return fmt::format("{} declares format '{}'", e.path().filename().string(),
                         j.at("format").get<std::string>().substr(0, 40));
  }
  return "";
}

}  // namespace

const BakedKindInfo& baked_folder_kind(const std::string& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(fmt::format("--baked {}: the folder does not exist", folder));
  const BakedKindInfo* found = nullptr;
  for (const BakedKindInfo& k : kBakedKinds) {
    if (!fs::exists(fs::path(folder) / k.manifest, ec)) continue;
    if (found)
      throw Error(fmt::format("--baked {}: holds both {} and {}; a bake folder is of one kind",
                              folder, found->manifest, k.manifest));
    found = &k;
  }
  if (!found) {
    const std::string format = declared_format(folder);
    throw Error(fmt::format("--baked {}: not a bake folder of a known kind ({}{}; known: {})",
                            folder, format.empty() ? "no manifest" : format,
                            format.empty() ? "" : ", not read by this illum", known_manifests()));
  }
  return *found;
}

void require_baked_kind(const std::string& folder, BakedKind kind, const std::string& command) {
  const BakedKindInfo& found = baked_folder_kind(folder);
  if (found.kind == kind) return;
  const char* wanted = "";
  for (const BakedKindInfo& k : kBakedKinds)
    if (k.kind == kind) wanted = k.name;
  throw Error(fmt::format("--baked {}: a {} folder; {} takes a {} folder", folder, found.name,
                          command, wanted));
}

}  // namespace illum::cli
