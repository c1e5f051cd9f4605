// The list of every real-time technique (technique_registry.cpp): adding a technique means
// adding its files and one line there. Listing needs no GPU and no scene.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "illum/realtime/technique.h"

namespace illum::realtime {

// A deque: registering one keeps references to the others (a Technique holds its decl).
using TechniqueList = std::deque<TechniqueDecl>;

// In frame order within each kind: globals, frame pipelines, shadow methods, add-ons; then
// the registered ones (TechniqueRegistration).
const TechniqueList& technique_registry();

// Throws InternalError naming the technique for a duplicate name, a name with a '.', or a
// dependency that is not declared, not an add-on, or part of a cycle. technique_registry()
// and TechniqueRegistration check with it.
void check_declarations(const TechniqueList& list);

// Adds a technique from outside the core (tests, examples) to the registry for the object's
// lifetime, after the built-in ones; checked as they are. Registrations end in reverse
// order; no renderer may use the technique after its registration ends.
class TechniqueRegistration {
 public:
  explicit TechniqueRegistration(TechniqueDecl decl);
  ~TechniqueRegistration();
  TechniqueRegistration(const TechniqueRegistration&) = delete;
  TechniqueRegistration& operator=(const TechniqueRegistration&) = delete;

 private:
  std::string name_;
};
// The declaration named `name`, or null.
const TechniqueDecl* find_technique(const std::string& name);
// The declaration named `name`; throws Error listing the known names of `kind` otherwise
// (`what` names the option, e.g. "--enable").
const TechniqueDecl& technique_of_kind(const std::string& name, TechniqueKind kind,
                                       const std::string& what);
std::vector<std::string> technique_names(TechniqueKind kind);

// `illum frame --list`: every technique with its parameters (type, default, range or
// values, per-frame or structural, alias, help) and its dependencies.
std::string technique_listing();
// The same as JSON: {"techniques": [{"name", "kind", "default_on" (add-ons),
// "switch_alias", "dependencies", "summary", "params": [{"name" (NAME.key), "key", "type",
// "default", "values" (enums), "min", "max", "change" (per-frame|structural), "alias", "help"}]}]}.
nlohmann::ordered_json technique_listing_json();

}  // namespace illum::realtime
