// What every harness shares: a scratch folder for the files an entry point reads, the split
// of one fuzz input into several files, the fixed companion files, and the rule that only
// illum::Error may leave a loader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "illum/core/error.h"

namespace illum::fuzz {

// Marks the boundary between two files inside one fuzz input (OBJ then MTL, manifest then
// atlas.bin). A line of its own, so text seeds stay readable and the dictionaries carry it.
inline constexpr std::string_view kNextFile = "\n--illum-fuzz-next-file--\n";

// A folder for this process's files, created on first use under /dev/shm (memory, fast)
// or the system temp folder, and removed when the process exits normally.
const std::filesystem::path& scratch_dir();

// Splits `data` at the first `max_parts - 1` occurrences of kNextFile. Always returns at
// least one part (possibly empty).
std::vector<std::string_view> split_files(const uint8_t* data, size_t size, size_t max_parts);

void write_file(const std::filesystem::path& path, std::string_view bytes);
// Writes `bytes` to `path`, or removes `path` when the part is absent, so a missing
// companion is a case the fuzzer can reach.
void write_or_remove(const std::filesystem::path& path, const std::string_view* bytes);

// Fixed companion files that fuzzed inputs may name (fuzz/README.md lists them):
//   tex.png (4×4 RGBA), tex.jpg (4×4), tex.hdr (4×4), tex.exr (4×4), normal.png (4×4),
//   env.hdr (8×4), env.exr (8×4), mesh.obj + mesh.mtl (two quads, objects "floor" and
//   "lamp", materials "white" and "light"), mesh.gltf (one triangle, data: URI),
//   buffer.bin (one triangle: 3 float3 positions then 3 uint16 indices).
void write_texture_companions(const std::filesystem::path& dir);
void write_mesh_companions(const std::filesystem::path& dir);

// Switches illum's log off: loader warnings would flood the fuzzer's output.
void quiet_logging();

// With ILLUM_FUZZ_VERBOSE set, says on stderr whether each input loaded or which illum::Error
// rejected it: for checking seeds and reading findings, not while fuzzing.
bool verbose();

// Runs one input through `load`. illum::Error is how bad input must be rejected and is
// swallowed; anything else (another exception type, an ILLUM_CHECK failure, a crash, a
// sanitizer report) escapes, and libFuzzer reports it as a finding.
template <typename Load>
void expect_only_illum_errors(Load&& load) {
  try {
    load();
    if (verbose()) fmt::print(stderr, "fuzz: loaded\n");
  } catch (const Error& e) {
    if (verbose()) fmt::print(stderr, "fuzz: rejected: {}\n", e.what());
  }
}

}  // namespace illum::fuzz
