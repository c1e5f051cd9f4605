// The atlas file (little-endian throughout):
//   "ILLUMATL"  8 bytes magic
//   u32 version (1), u32 width, u32 height, f32 texel_size, u32 chart_count, u32 mesh_count
//   chart_count × { u32 mesh, u32 x, u32 y, u32 width, u32 height }
//   mesh_count × { u32 source_vertex_count, u32 vertex_count, u32 index_count,
//                  u32 triangle_chart_count (0 or index_count / 3),
//                  u32 source_vertex[vertex_count], f32 uv1[2 · vertex_count],
//                  u32 indices[index_count], u32 triangle_chart[triangle_chart_count] }
// and nothing after. Every count is checked against the bytes left before anything is
// allocated, so a corrupt count cannot ask for gigabytes.
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "illum/atlas/atlas.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"

namespace illum::atlas {
namespace {

constexpr char kMagic[8] = {'I', 'L', 'L', 'U', 'M', 'A', 'T', 'L'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kMaxSize = 65536;

// Checks what load_atlas promises and save_atlas relies on; `where` prefixes messages.
void validate(const Atlas& atlas, const std::string& where) {
  auto fail = [&](const std::string& what) { throw Error(fmt::format("{}: {}", where, what)); };
  if (atlas.width < 1 || atlas.height < 1 || uint32_t(atlas.width) > kMaxSize ||
      uint32_t(atlas.height) > kMaxSize)
    fail(fmt::format("atlas size {}×{} is outside [1, {}]", atlas.width, atlas.height, kMaxSize));
  if (!std::isfinite(atlas.texel_size) || atlas.texel_size < 0.0f)
    fail(fmt::format("texel size {} is not a finite number ≥ 0", atlas.texel_size));
  if (atlas.chart_count < 0) fail(fmt::format("chart count {} is negative", atlas.chart_count));
  if (!atlas.charts.empty() && atlas.charts.size() != size_t(atlas.chart_count))
    fail(fmt::format("chart count {} but {} chart rectangles", atlas.chart_count,
                     atlas.charts.size()));
  for (size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& r = atlas.charts[c];
    if (r.mesh < 0 || size_t(r.mesh) >= atlas.meshes.size())
      fail(fmt::format("chart {} belongs to mesh {} of {}", c, r.mesh, atlas.meshes.size()));
    if (r.x < 0 || r.y < 0 || r.width < 1 || r.height < 1 || r.x > atlas.width - r.width ||
        r.y > atlas.height - r.height)
      fail(fmt::format("chart {} rectangle ({}, {}) {}×{} is outside the {}×{} atlas", c, r.x, r.y,
                       r.width, r.height, atlas.width, atlas.height));
  }
  for (size_t m = 0; m < atlas.meshes.size(); ++m) {
    const MeshLayout& mesh = atlas.meshes[m];
    const size_t vertices = mesh.source_vertex.size();
    if (mesh.uv1.size() != vertices)
      fail(fmt::format("mesh {} has {} uv1 for {} vertices", m, mesh.uv1.size(), vertices));
    if (mesh.indices.size() % 3 != 0)
      fail(fmt::format("mesh {} has {} indices, not a multiple of 3", m, mesh.indices.size()));
    const size_t triangles = mesh.indices.size() / 3;
    if (!mesh.triangle_chart.empty() && mesh.triangle_chart.size() != triangles)
      fail(fmt::format("mesh {} has {} triangle charts for {} triangles", m,
                       mesh.triangle_chart.size(), triangles));
    for (size_t i = 0; i < vertices; ++i) {
      if (mesh.source_vertex[i] >= mesh.source_vertex_count)
        fail(fmt::format("mesh {} vertex {} comes from source vertex {}, but there are only {}", m,
                         i, mesh.source_vertex[i], mesh.source_vertex_count));
      const vec2 uv = mesh.uv1[i];
      if (!(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f))
        fail(fmt::format("mesh {} vertex {} has uv1 ({}, {}) outside [0,1]", m, i, uv.x, uv.y));
    }
    for (size_t i = 0; i < mesh.indices.size(); ++i)
      if (mesh.indices[i] >= vertices)
        fail(fmt::format("mesh {} triangle {} uses vertex {}, but it has only {}", m, i / 3,
                         mesh.indices[i], vertices));
    for (size_t t = 0; t < mesh.triangle_chart.size(); ++t) {
      const uint32_t c = mesh.triangle_chart[t];
      if (c == kNoChart) continue;
      if (c >= uint32_t(atlas.chart_count))
        fail(fmt::format("mesh {} triangle {} is in chart {} of {}", m, t, c, atlas.chart_count));
      if (!atlas.charts.empty() && atlas.charts[c].mesh != int(m))
        fail(fmt::format("mesh {} triangle {} is in chart {}, which belongs to mesh {}", m, t, c,
                         atlas.charts[c].mesh));
    }
  }
}

class Writer {
 public:
  void bytes(const void* data, size_t size) { out_.append(static_cast<const char*>(data), size); }
  void u32(uint32_t v) {
    const char b[4] = {char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff),
                       char((v >> 24) & 0xff)};
    out_.append(b, 4);
  }
  void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
  const std::string& data() const { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(std::string data, std::string where) : data_(std::move(data)), where_(std::move(where)) {}

  void need(size_t bytes, const char* what) const {
    if (data_.size() - pos_ < bytes)
      throw Error(fmt::format("{}: truncated: {} needs {} bytes at offset {}, the file has {}",
                              where_, what, bytes, pos_, data_.size()));
  }
  void bytes(void* out, size_t size, const char* what) {
    need(size, what);
    std::memcpy(out, data_.data() + pos_, size);
    pos_ += size;
  }
  uint32_t u32(const char* what) {
    need(4, what);
    const auto* b = reinterpret_cast<const unsigned char*>(data_.data() + pos_);
    pos_ += 4;
    return uint32_t(b[0]) | (uint32_t(b[1]) << 8) | (uint32_t(b[2]) << 16) | (uint32_t(b[3]) << 24);
  }
  float f32(const char* what) { return std::bit_cast<float>(u32(what)); }
  // Checks that `count` items of `item_bytes` each are there before they are allocated.
  void need_items(uint64_t count, size_t item_bytes, const char* what) const {
    if (count > (data_.size() - pos_) / item_bytes)
      throw Error(
          fmt::format("{}: truncated or malformed: {} {} need {} bytes at offset {}, the "
                      "file has {}",
                      where_, count, what, count * item_bytes, pos_, data_.size()));
  }
  bool at_end() const { return pos_ == data_.size(); }
  size_t position() const { return pos_; }

 private:
  std::string data_;
  std::string where_;
  size_t pos_ = 0;
};

}  // namespace

void save_atlas(const Atlas& atlas, const std::filesystem::path& path) {
  const std::string where = fmt::format("save_atlas '{}'", path.string());
  validate(atlas, where);
  Writer w;
  w.bytes(kMagic, sizeof(kMagic));
  w.u32(kVersion);
  w.u32(uint32_t(atlas.width));
  w.u32(uint32_t(atlas.height));
  w.f32(atlas.texel_size);
  w.u32(uint32_t(atlas.chart_count));
  w.u32(uint32_t(atlas.meshes.size()));
  // Charts are all or nothing: a hand-made atlas without rectangles writes none.
  if (atlas.charts.empty() && atlas.chart_count > 0)
    throw Error(
        fmt::format("{}: chart count {} but no chart rectangles", where, atlas.chart_count));
  for (const AtlasChart& c : atlas.charts) {
    w.u32(uint32_t(c.mesh));
    w.u32(uint32_t(c.x));
    w.u32(uint32_t(c.y));
    w.u32(uint32_t(c.width));
    w.u32(uint32_t(c.height));
  }
  for (const MeshLayout& mesh : atlas.meshes) {
    w.u32(mesh.source_vertex_count);
    w.u32(uint32_t(mesh.source_vertex.size()));
    w.u32(uint32_t(mesh.indices.size()));
    w.u32(uint32_t(mesh.triangle_chart.size()));
    for (uint32_t v : mesh.source_vertex) w.u32(v);
    for (const vec2& uv : mesh.uv1) {
      w.f32(uv.x);
      w.f32(uv.y);
    }
    for (uint32_t i : mesh.indices) w.u32(i);
    for (uint32_t c : mesh.triangle_chart) w.u32(c);
  }

  // Checked to the last byte and renamed into place (core/file_write.h): a full disk is one
  // error and leaves neither a partial atlas nor a temporary file.
  write_file_atomically(path.string(), w.data());
}

Atlas load_atlas(const std::filesystem::path& path) {
  const std::string where = fmt::format("atlas file '{}'", path.string());
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(fmt::format("{}: not found (or not a file)", where));
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(fmt::format("{}: cannot read its size: {}", where, ec.message()));
  std::string data(size_t(size), '\0');
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(fmt::format("{}: cannot open", where));
    in.read(data.data(), std::streamsize(data.size()));
    if (!in || in.gcount() != std::streamsize(data.size()))
      throw Error(fmt::format("{}: read error", where));
  }
  Reader r(std::move(data), where);
  char magic[sizeof(kMagic)];
  r.bytes(magic, sizeof(magic), "the magic");
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throw Error(fmt::format("{}: not an illum atlas (the magic is not ILLUMATL)", where));
  const uint32_t version = r.u32("the version");
  if (version != kVersion)
    throw Error(fmt::format("{}: version {} is not supported (this illum reads version {})", where,
                            version, kVersion));
  Atlas atlas;
  const uint32_t width = r.u32("the width"), height = r.u32("the height");
  if (width < 1 || height < 1 || width > kMaxSize || height > kMaxSize)
    throw Error(
        fmt::format("{}: atlas size {}×{} is outside [1, {}]", where, width, height, kMaxSize));
  atlas.width = int(width);
  atlas.height = int(height);
  atlas.texel_size = r.f32("the texel size");
  const uint32_t chart_count = r.u32("the chart count");
  const uint32_t mesh_count = r.u32("the mesh count");
  if (chart_count > uint32_t(std::numeric_limits<int>::max()))
    throw Error(fmt::format("{}: chart count {} is too large", where, chart_count));
  atlas.chart_count = int(chart_count);
  r.need_items(chart_count, 20, "charts");
  atlas.charts.resize(chart_count);
  for (AtlasChart& c : atlas.charts) {
    uint32_t values[5];  // mesh, x, y, width, height
    for (uint32_t& v : values) v = r.u32("a chart");
    if (values[0] >= mesh_count)
      throw Error(fmt::format("{}: malformed: a chart belongs to mesh {} of {}", where, values[0],
                              mesh_count));
    for (int i = 1; i < 5; ++i)  // so they fit an int; validate() checks them against the size
      if (values[i] > kMaxSize)
        throw Error(fmt::format("{}: malformed: chart rectangle value {} is out of range", where,
                                values[i]));
    c = {int(values[0]), int(values[1]), int(values[2]), int(values[3]), int(values[4])};
  }
  r.need_items(mesh_count, 16, "meshes");
  atlas.meshes.resize(mesh_count);
  for (uint32_t m = 0; m < mesh_count; ++m) {
    MeshLayout& mesh = atlas.meshes[m];
    mesh.source_vertex_count = r.u32("a mesh header");
    const uint32_t vertices = r.u32("a mesh header");
    const uint32_t indices = r.u32("a mesh header");
    const uint32_t triangle_charts = r.u32("a mesh header");
    r.need_items(uint64_t(vertices), 12, "vertices");
    mesh.source_vertex.resize(vertices);
    for (uint32_t& v : mesh.source_vertex) v = r.u32("source vertices");
    mesh.uv1.resize(vertices);
    for (vec2& uv : mesh.uv1) {
      uv.x = r.f32("uv1");
      uv.y = r.f32("uv1");
    }
    r.need_items(indices, 4, "indices");
    mesh.indices.resize(indices);
    for (uint32_t& i : mesh.indices) i = r.u32("indices");
    r.need_items(triangle_charts, 4, "triangle charts");
    mesh.triangle_chart.resize(triangle_charts);
    for (uint32_t& c : mesh.triangle_chart) c = r.u32("triangle charts");
  }
  if (!r.at_end())
    throw Error(fmt::format("{}: malformed: unexpected bytes after the last mesh at offset {}",
                            where, r.position()));
  validate(atlas, where + ": malformed");
  return atlas;
}

}  // namespace illum::atlas
