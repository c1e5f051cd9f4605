#include "illum/core/file_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"

namespace illum {

namespace fs = std::filesystem;

namespace {

// NAME_MAX of the file systems illum writes to (ext4, xfs, tmpfs, btrfs).
constexpr size_t kMaxFileNameBytes = 255;

std::string system_reason(int error) {
  return std::strerror(error);
}

// Writes all of `parts`, in order, to a new file `tmp`; returns "" or the reason it failed.
std::string write_all(const std::string& tmp, const std::vector<std::span<const uint8_t>>& parts) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return system_reason(errno);
  std::string failure;
  for (const std::span<const uint8_t>& bytes : parts) {
    size_t done = 0;
    while (done < bytes.size() && failure.empty()) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        failure = n < 0 ? system_reason(errno) : "the disk took no more bytes";
      else
        done += static_cast<size_t>(n);
    }
  }
  if (failure.empty() && ::fsync(fd) != 0) failure = system_reason(errno);
  if (::close(fd) != 0 && failure.empty()) failure = system_reason(errno);
  return failure;
}

}  // namespace

std::string temporary_path_beside(const std::string& path) {
  static std::atomic<uint64_t> counter{0};
  const fs::path target(path);
  std::string name = target.filename().string();
  // Keep the hidden name within NAME_MAX even for a target name near the limit.
  const std::string suffix = fmt::format(".{}-{}.tmp", getpid(), counter++);
  if (name.size() + suffix.size() + 1 > kMaxFileNameBytes)
    name.resize(kMaxFileNameBytes - suffix.size() - 1);
  return (target.parent_path() / ("." + name + suffix)).string();
}

void write_file_atomically(const std::string& path, std::span<const uint8_t> bytes) {
  write_file_atomically(path, std::vector<std::span<const uint8_t>>{bytes});
}

void write_file_atomically(const std::string& path,
                           const std::vector<std::span<const uint8_t>>& parts) {
  const std::string tmp = temporary_path_beside(path);
  const StagingPath staged(tmp);  // a second Ctrl-C removes it
  std::string failure = write_all(tmp, parts);
  std::error_code ec;
  if (failure.empty()) {
    fs::rename(tmp, path, ec);
    if (ec) failure = ec.message();
  }
  if (!failure.empty()) {
    fs::remove(tmp, ec);
    throw Error(fmt::format("{}: cannot write ({})", path, failure));
  }
}

void write_file_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(
      path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

void check_writable_output(const std::string& path) {
  const fs::path target(path);
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw Error(fmt::format("{}: an output needs a file name", path));
  if (name.size() > kMaxFileNameBytes)
    throw Error(
        fmt::format("{}: the file name is {} bytes long, more than the {} a file system "
                    "takes",
                    path.substr(0, 60) + "…", name.size(), kMaxFileNameBytes));
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(fmt::format("{}: output folder '{}' does not exist", path, folder.string()));
  if (::access(folder.c_str(), W_OK) != 0)
    throw Error(fmt::format("{}: cannot write in folder '{}' ({})", path, folder.string(),
                            system_reason(errno)));
  if (fs::is_directory(target, ec))
    throw Error(fmt::format("{}: is a folder, not a file name", path));
}

}  // namespace illum
