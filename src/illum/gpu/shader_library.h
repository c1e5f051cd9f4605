// Embedded SPIR-V: every shaders/*.{vert,frag,comp} is compiled by glslc at build time and
// linked into the binary (target illum_shaders), looked up by file name ("forward.frag").
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace illum::gpu {

// The SPIR-V words of an embedded shader; empty when no shader has that name.
std::span<const uint32_t> shader_spirv(std::string_view name);
std::vector<std::string_view> shader_names();

}  // namespace illum::gpu
