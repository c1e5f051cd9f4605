#include "fuzz_support.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "illum/core/image.h"
#include "illum/core/log.h"

namespace illum::fuzz {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kScratchPrefix = "illum-fuzz-";

void remove_scratch_dir() {
  std::error_code ignored;
  fs::remove_all(scratch_dir(), ignored);
}

// A process that crashed (a finding) never ran its atexit handler: remove the folders of
// harness processes that no longer exist.
void remove_stale_scratch_dirs(const fs::path& root) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(kScratchPrefix)) continue;
    const long pid = std::strtol(name.c_str() + kScratchPrefix.size(), nullptr, 10);
    if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) stale.push_back(entry.path());
  }
  for (const fs::path& dir : stale) fs::remove_all(dir, ec);
}

// A small image whose texels all differ, so a decoder that drops or swaps rows shows.
Image gradient(int width, int height, int channels) {
  Image image(width, height, channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c)
        image.pixel(x, y)[c] = float((x + 1) * (y + 2) * (c + 3) % 17) / 16.0f;
  return image;
}

}  // namespace

const fs::path& scratch_dir() {
  static const fs::path dir = [] {
    std::error_code ec;
    const fs::path root =
        fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    remove_stale_scratch_dirs(root);
    fs::path d = root / fmt::format("{}{}", kScratchPrefix, ::getpid());
    fs::remove_all(d, ec);
    fs::create_directories(d);
    return d;
  }();
  // Registered after `dir` is built, so it runs before `dir` is destroyed at exit.
  [[maybe_unused]] static const bool removed_at_exit = std::atexit(remove_scratch_dir) == 0;
  return dir;
}

std::vector<std::string_view> split_files(const uint8_t* data, size_t size, size_t max_parts) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  std::vector<std::string_view> parts;
  while (parts.size() + 1 < max_parts) {
    const size_t at = rest.find(kNextFile);
    if (at == std::string_view::npos) break;
    parts.push_back(rest.substr(0, at));
    rest.remove_prefix(at + kNextFile.size());
  }
  parts.push_back(rest);
  return parts;
}

void write_file(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) {
    // The harness cannot do its job; stop loudly rather than fuzz a stale file.
    fmt::print(stderr, "fuzz: cannot write {}\n", path.string());
    std::abort();
  }
}

void write_or_remove(const fs::path& path, const std::string_view* bytes) {
  if (bytes) {
    write_file(path, *bytes);
  } else {
    std::error_code ignored;
    fs::remove(path, ignored);
  }
}

void write_texture_companions(const fs::path& dir) {
  write_image((dir / "tex.png").string(), gradient(4, 4, 4));
  write_image((dir / "tex.jpg").string(), gradient(4, 4, 3));
  write_image((dir / "tex.hdr").string(), gradient(4, 4, 3));
  write_image((dir / "tex.exr").string(), gradient(4, 4, 3));
  ImageWriteOptions linear;
  linear.srgb = false;
  write_image((dir / "normal.png").string(), gradient(4, 4, 3), linear);
  write_image((dir / "env.hdr").string(), gradient(8, 4, 3));
  write_image((dir / "env.exr").string(), gradient(8, 4, 3));
}

void write_mesh_companions(const fs::path& dir) {
  write_file(dir / "mesh.obj", R"(mtllib mesh.mtl
o floor
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 1 0
usemtl white
f 1/1/1 4/4/1 3/3/1 2/2/1
o lamp
v -0.2 1 -0.2
v 0.2 1 -0.2
v 0.2 1 0.2
v -0.2 1 0.2
usemtl light
f 5 6 7 8
)");
  write_file(dir / "mesh.mtl", R"(newmtl white
Kd 0.7 0.7 0.7
map_Kd tex.png
norm normal.png
newmtl light
Kd 0 0 0
Ke 5 5 5
)");
  // One triangle: three float3 positions, then three uint16 indices, padded to 4 bytes.
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint16_t indices[4] = {0, 1, 2, 0};
  std::string buffer(sizeof positions + sizeof indices, '\0');
  std::memcpy(buffer.data(), positions, sizeof positions);
  std::memcpy(buffer.data() + sizeof positions, indices, sizeof indices);
  write_file(dir / "buffer.bin", buffer);
  write_file(dir / "mesh.gltf", R"({"asset": {"version": "2.0"}, "scene": 0,
 "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "tri"}],
 "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
   "material": 0}]}],
 "materials": [{"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1]}}],
 "buffers": [{"uri": "buffer.bin", "byteLength": 44}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                 {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]},
               {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}
)");
}

bool verbose() {
  static const bool on = std::getenv("ILLUM_FUZZ_VERBOSE") != nullptr;
  return on;
}

void quiet_logging() {
  log::set_level(log::Level::kOff);
}

}  // namespace illum::fuzz
