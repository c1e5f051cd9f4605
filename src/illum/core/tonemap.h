// CPU tone mappers for writing 8-bit previews of linear HDR images (the GPU side has its
// own shader versions in shaders/). HDR files are always written linear, untouched.
#pragma once

#include <string>

#include "illum/core/color.h"
#include "illum/core/image.h"

namespace illum {

enum class ToneMapper { kClamp, kReinhard, kAces, kAgx };

// "clamp" | "reinhard" | "aces" | "agx" (the real-time tonemap pass's four, operation for
// operation as shaders/tonemap.comp); throws Error for anything else.
ToneMapper tone_mapper_from_string(const std::string& name);

// Maps linear radiance × exposure to [0,1] linear display values (sRGB encoding happens
// when the 8-bit file is written).
Color tone_map(const Color& c, ToneMapper mapper);

// Returns a copy of `hdr` with `exposure` applied and tone mapped (alpha kept).
Image tone_mapped(const Image& hdr, ToneMapper mapper, float exposure);

}  // namespace illum
