// Files that reach the disk whole or not at all. A buffered write to a full disk (or past a
// file-size limit) can report success and leave a truncated file: every byte written here
// is checked through write(2), fsync and close, and the file appears under its name only by
// a rename once all of that succeeded.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace illum {

// Writes `bytes` to `path` through a hidden temporary file in the same folder, fsyncs it and
// renames it over `path`. Throws Error naming `path` and the system's reason (e.g. "No
// space left on device") when any step fails; the temporary file is removed then and
// `path` is left as it was.
void write_file_atomically(const std::string& path, std::span<const uint8_t> bytes);
void write_file_atomically(const std::string& path, const std::string& text);
// The concatenation of `parts` (a header and a large block, say, without copying them).
void write_file_atomically(const std::string& path,
                           const std::vector<std::span<const uint8_t>>& parts);

// The bytes of a trivially copyable value or array, for the `parts` above.
template <typename T>
std::span<const uint8_t> bytes_of(const T* data, size_t count = 1) {
  return {reinterpret_cast<const uint8_t*>(data), count * sizeof(T)};
}

// The hidden temporary name write_file_atomically uses beside `path`: same folder (so the
// rename is atomic), unique per process and call.
std::string temporary_path_beside(const std::string& path);

// Refuses a path whose file name is longer than the file system takes (255 bytes), whose
// folder does not exist or is not writable: one line naming the path. For commands to call
// on every output before any long work starts.
void check_writable_output(const std::string& path);

}  // namespace illum
