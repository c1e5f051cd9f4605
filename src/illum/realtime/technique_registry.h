// The list of every real-time technique (technique_registry.cpp): adding a technique means
// adding its files and one line there. Listing needs no GPU and no scene.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/realtime/technique.h"

namespace illum::realtime {

// In frame order within each kind: globals, frame pipelines, shadow methods, add-ons.
const std::vector<TechniqueDecl>& technique_registry();
// The declaration named `name`, or null.
const TechniqueDecl* find_technique(const std::string& name);
// The declaration named `name`; throws Error listing the known names of `kind` otherwise
// (`what` names the option, e.g. "--enable").
const TechniqueDecl& technique_of_kind(const std::string& name, TechniqueKind kind,
                                       const std::string& what);
std::vector<std::string> technique_names(TechniqueKind kind);

// `illum frame --list`: every technique with its parameters (type, default, range or
// values, per-frame or structural, alias, help).
std::string technique_listing();
// The same as JSON: {"techniques": [{"name", "kind", "default_on" (add-ons),
// "switch_alias", "summary", "params": [{"name" (NAME.key), "key", "type", "default",
// "values" (enums), "min", "max", "change" (per-frame|structural), "alias", "help"}]}]}.
nlohmann::ordered_json technique_listing_json();

}  // namespace illum::realtime
