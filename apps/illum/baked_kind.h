// The kinds of folder `illum bake` writes, told by the manifest each holds: what `--baked DIR`
// reads in every command (frame and view show any kind, baked_display.h; export takes a
// light-map, relight a PRT folder). A new kind is one more entry in kBakedKinds.
#pragma once

#include <string>

namespace illum::cli {

enum class BakedKind { kLightmap, kPrt, kProbes };

struct BakedKindInfo {
  BakedKind kind;
  const char* name;      // for messages
  const char* manifest;  // the file that tells the kind
};

// The kind of `folder`; throws Error (one line naming `--baked folder`) for a missing folder,
// one of no or an unknown kind, or one holding two manifests.
const BakedKindInfo& baked_folder_kind(const std::string& folder);

// `folder`, checked to be of `kind`: another kind is refused with one line saying what
// `command` takes.
void require_baked_kind(const std::string& folder, BakedKind kind, const std::string& command);

}  // namespace illum::cli
