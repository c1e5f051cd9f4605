// Light-map atlas: charts by region growing over welded edges, planar projection at a uniform
// world-space texel density, injectivity repair, minimal-area rotation and skyline packing.
// The choices and their reasons are in README.md.
#include "illum/atlas/atlas.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/mesh_processing.h"

namespace illum::atlas {

using glm::dvec2;
using glm::dvec3;

AtlasOptions AtlasOptions::from_params(const Params& params) {
  AtlasOptions o;
  o.resolution = params.get_int_in("resolution", o.resolution, kMinResolution, kMaxResolution);
  o.texel_size = params.get<float>("texel_size", o.texel_size);
  if (o.texel_size < 0.0f)
    throw Error(fmt::format("{} = {} must be ≥ 0 (metres per texel; 0 = the finest that fits)",
                            params.where("texel_size"), o.texel_size));
  o.padding = params.get_int_in("padding", o.padding, 1, 16);
  o.max_chart_angle = params.get<float>("max_chart_angle", o.max_chart_angle);
  if (!(o.max_chart_angle > 0.0f && o.max_chart_angle <= 89.0f))
    throw Error(fmt::format("{} = {} is outside (0, 89] degrees", params.where("max_chart_angle"),
                            o.max_chart_angle));
  return o;
}

namespace {

// A chart's vertices sit at least this far (in texels) inside its reserved cells, so float
// rounding of uv1 never moves a vertex into a neighbouring texel.
constexpr double kCellMargin = 1.0 / 256.0;
// Positions closer than this fraction of the mesh's world diagonal are one vertex for
// adjacency (loaders split vertices at normal/uv seams; exporters may round differently).
constexpr double kWeldRelTolerance = 1e-6;
// The texel-size search stops when the finest size that fits is bracketed this tightly.
constexpr double kSearchRelPrecision = 1e-3;
// Charts with at most this many triangles are checked for overlaps pair by pair.
constexpr size_t kBruteForceOverlap = 16;
// A chart covering less than this fraction of its rectangle is split, when the space it
// wastes exceeds kMaxChartWaste of the scene's surface area (rings, long thin L-shapes).
constexpr double kMinChartFill = 0.25;
constexpr double kMaxChartWaste = 1e-4;
// Charts of at least this many cells filling less than this fraction of their rectangle
// lend its free space to smaller charts.
constexpr double kHostFill = 0.85;
constexpr int kMinHostCells = 1024;
// A host's free space is searched on at most about this many blocks of cells, and
// handed out as at most this many rectangles (the largest first).
constexpr double kMaxHostBlocks = 1 << 16;
constexpr int kMaxHolesPerHost = 12;

void validate_options(const AtlasOptions& o) {
  if (o.resolution < kMinResolution || o.resolution > kMaxResolution)
    throw Error(fmt::format("atlas: resolution {} is outside [{}, {}]", o.resolution,
                            kMinResolution, kMaxResolution));
  if (!std::isfinite(o.texel_size) || o.texel_size < 0.0f)
    throw Error(fmt::format("atlas: texel_size {} must be finite and ≥ 0", o.texel_size));
  if (o.padding < 1 || o.padding > 16)
    throw Error(fmt::format("atlas: padding {} is outside [1, 16]", o.padding));
  if (!(o.max_chart_angle > 0.0f && o.max_chart_angle <= 89.0f))
    throw Error(
        fmt::format("atlas: max_chart_angle {} is outside (0, 89] degrees", o.max_chart_angle));
}

std::string mesh_label(const Mesh& mesh, size_t index) {
  return fmt::format("mesh '{}' (#{})", mesh.name, index);
}

// ---------------------------------------------------------------------------------------------
// World-space geometry of one mesh and its triangle adjacency.

struct MeshGeometry {
  std::vector<dvec3> position;           // world space, per vertex
  std::vector<dvec3> normal;             // unit face normal per triangle (zero if degenerate)
  std::vector<double> area;              // world-space area per triangle
  std::vector<uint8_t> degenerate;       // per triangle
  std::vector<uint32_t> adjacent_begin;  // CSR over triangles: neighbours sharing a welded edge
  std::vector<uint32_t> adjacent;
  double weld_tolerance = 0.0;

  size_t triangle_count() const { return area.size(); }
  std::span<const uint32_t> neighbours(uint32_t t) const {
    return {adjacent.data() + adjacent_begin[t], adjacent.data() + adjacent_begin[t + 1]};
  }
};

// Welds vertices whose world positions lie within `tolerance` of each other: the first vertex
// (in index order) of a cluster represents it, so the result does not depend on hashing.
std::vector<uint32_t> weld_vertices(const std::vector<dvec3>& p, const dvec3& origin,
                                    double tolerance) {
  std::vector<uint32_t> weld(p.size());
  if (!(tolerance > 0.0)) {  // a mesh shrunk to one point: all vertices coincide
    std::fill(weld.begin(), weld.end(), 0u);
    return weld;
  }
  // Cells of the tolerance's size: points within the tolerance lie in the same or an adjacent
  // cell. Coordinates relative to the bounding box stay below 1/kWeldRelTolerance cells.
  struct CellHash {
    size_t operator()(const glm::i64vec3& c) const {
      uint64_t h = uint64_t(c.x) * 0x9E3779B97F4A7C15ull;
      h ^= uint64_t(c.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
      h ^= uint64_t(c.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
      return size_t(h);
    }
  };
  std::unordered_map<glm::i64vec3, uint32_t, CellHash> head;  // cell → first representative
  std::vector<uint32_t> next_in_cell(p.size(), UINT32_MAX);
  head.reserve(p.size());
  const double tol_sq = tolerance * tolerance;
  auto cell_of = [&](const dvec3& q) { return glm::i64vec3(glm::floor((q - origin) / tolerance)); };
  for (uint32_t v = 0; v < p.size(); ++v) {
    const glm::i64vec3 c = cell_of(p[v]);
    uint32_t found = UINT32_MAX;
    for (int dz = -1; dz <= 1 && found == UINT32_MAX; ++dz)
      for (int dy = -1; dy <= 1 && found == UINT32_MAX; ++dy)
        for (int dx = -1; dx <= 1 && found == UINT32_MAX; ++dx) {
          auto it = head.find(c + glm::i64vec3(dx, dy, dz));
          if (it == head.end()) continue;
          for (uint32_t r = it->second; r != UINT32_MAX; r = next_in_cell[r]) {
            const dvec3 d = p[r] - p[v];
            if (glm::dot(d, d) <= tol_sq) {
              found = r;
              break;
            }
          }
        }
    if (found != UINT32_MAX) {
      weld[v] = weld[found];
      continue;
    }
    weld[v] = v;
    auto [it, inserted] = head.try_emplace(c, v);
    if (!inserted) {  // append to the cell's list, keeping index order
      uint32_t last = it->second;
      while (next_in_cell[last] != UINT32_MAX) last = next_in_cell[last];
      next_in_cell[last] = v;
    }
  }
  return weld;
}

MeshGeometry mesh_geometry(const Mesh& mesh, size_t mesh_index, const mat4& transform) {
  const size_t vertex_count = mesh.positions.size();
  if (mesh.indices.size() % 3 != 0)
    throw Error(fmt::format("atlas: {} has {} indices, not a multiple of 3",
                            mesh_label(mesh, mesh_index), mesh.indices.size()));
  MeshGeometry g;
  g.position.assign(vertex_count, dvec3(0.0));
  const glm::dmat4 m(transform);
  Bounds3 bounds;
  for (size_t v = 0; v < vertex_count; ++v) {
    g.position[v] = dvec3(m * glm::dvec4(dvec3(mesh.positions[v]), 1.0));
    if (!std::isfinite(g.position[v].x) || !std::isfinite(g.position[v].y) ||
        !std::isfinite(g.position[v].z))
      throw Error(fmt::format("atlas: {} has a non-finite world position at vertex {}",
                              mesh_label(mesh, mesh_index), v));
    bounds.extend(vec3(g.position[v]));
  }
  const size_t n = mesh.triangle_count();
  for (size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= vertex_count)
      throw Error(fmt::format("atlas: {} triangle {} uses vertex {}, but it has only {} vertices",
                              mesh_label(mesh, mesh_index), i / 3, mesh.indices[i], vertex_count));

  const double diagonal = double(bounds.diagonal());
  const double scale_sq = diagonal * diagonal;
  g.normal.assign(n, dvec3(0.0));
  g.area.assign(n, 0.0);
  g.degenerate.assign(n, 0);
  for (size_t t = 0; t < n; ++t) {
    const uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1],
                   i2 = mesh.indices[3 * t + 2];
    const dvec3 &a = g.position[i0], &b = g.position[i1], &c = g.position[i2];
    const dvec3 cross = glm::cross(b - a, c - a);
    const double length = glm::length(cross);
    // The loader's rule, applied in world space (a transform may flatten a triangle).
    if (is_degenerate_triangle(vec3(a), vec3(b), vec3(c), i0, i1, i2, scale_sq) ||
        !(length > 0.0)) {
      g.degenerate[t] = 1;
      continue;
    }
    g.normal[t] = cross / length;
    g.area[t] = 0.5 * length;
  }

  g.weld_tolerance = kWeldRelTolerance * diagonal;
  const std::vector<uint32_t> weld =
      weld_vertices(g.position, dvec3(bounds.empty() ? vec3(0.0f) : bounds.min), g.weld_tolerance);
  // Edges as (welded vertex pair, triangle), sorted: equal keys are one shared edge.
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  edges.reserve(3 * n);
  for (uint32_t t = 0; t < n; ++t) {
    if (g.degenerate[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = weld[mesh.indices[3 * t + k]];
      const uint32_t b = weld[mesh.indices[3 * t + (k + 1) % 3]];
      if (a == b) continue;
      edges.emplace_back((uint64_t(std::min(a, b)) << 32) | std::max(a, b), t);
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<uint64_t> pairs;  // (t1 << 32 | t2), both directions
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (size_t p = i; p < j; ++p)
      for (size_t q = i; q < j; ++q)
        if (edges[p].second != edges[q].second)
          pairs.push_back((uint64_t(edges[p].second) << 32) | edges[q].second);
    i = j;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  g.adjacent_begin.assign(n + 1, 0);
  g.adjacent.resize(pairs.size());
  for (size_t i = 0; i < pairs.size(); ++i) {
    ++g.adjacent_begin[(pairs[i] >> 32) + 1];
    g.adjacent[i] = uint32_t(pairs[i]);
  }
  for (size_t t = 0; t < n; ++t) g.adjacent_begin[t + 1] += g.adjacent_begin[t];
  return g;
}

// ---------------------------------------------------------------------------------------------
// Charts.

// A connected set of triangles in breadth-first order from its first one, with the axis it
// is projected along (every normal within the angle limit of it).
struct Region {
  std::vector<uint32_t> triangles;
  dvec3 axis{0.0};
};

// A finished chart: local 2-D coordinates in metres, rotated to the minimal-area bounding
// rectangle, lying (size.x ≥ size.y), with its minimum corner at the origin.
struct Chart {
  int mesh = 0;
  std::vector<uint32_t> triangles;
  std::vector<dvec2> corners;  // 3 per triangle, in `triangles` order
  dvec2 size{0.0};
  double area = 0.0;  // of the projected triangles, m²

  double fill() const { return size.x * size.y > 0.0 ? area / (size.x * size.y) : 1.0; }
};

// Duff et al. 2017 orthonormal basis in double precision: (t, b, n) right-handed, so a
// triangle facing the axis projects counter-clockwise.
void basis_of(const dvec3& n, dvec3& t, dvec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = dvec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = dvec3(c, sign + n.y * n.y * a, -n.y);
}

double cross2(const dvec2& a, const dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// Smallest cosine between the axis and the region's normals (the largest deviation).
double min_cosine(const MeshGeometry& g, std::span<const uint32_t> tris, const dvec3& axis) {
  double m = 1.0;
  for (uint32_t t : tris) m = std::min(m, glm::dot(g.normal[t], axis));
  return m;
}

// The better of `fallback` (valid by construction) and the area-weighted mean normal: the one
// whose largest deviation is smaller. Projecting along the mean spreads the cos θ area loss
// evenly, e.g. both slopes of a roof instead of one.
dvec3 choose_axis(const MeshGeometry& g, std::span<const uint32_t> tris, const dvec3& fallback) {
  dvec3 sum(0.0);
  for (uint32_t t : tris) sum += g.area[t] * g.normal[t];
  const double length = glm::length(sum);
  if (!(length > 0.0)) return fallback;
  const dvec3 mean = sum / length;
  return min_cosine(g, tris, mean) >= min_cosine(g, tris, fallback) ? mean : fallback;
}

std::vector<dvec2> project(const Mesh& mesh, const MeshGeometry& g, const Region& region) {
  dvec3 t, b;
  basis_of(region.axis, t, b);
  // Relative to one of the chart's points, so far-away charts keep their precision.
  const dvec3 origin = g.position[mesh.indices[3 * region.triangles[0]]];
  std::vector<dvec2> corners(3 * region.triangles.size());
  for (size_t i = 0; i < region.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const dvec3 p = g.position[mesh.indices[3 * region.triangles[i] + k]] - origin;
      corners[3 * i + k] = dvec2(glm::dot(p, t), glm::dot(p, b));
    }
  return corners;
}

// Interior overlap of two counter-clockwise triangles by separating axes (their six edge
// normals); touching within `tolerance` (shared edges and vertices) is no overlap.
bool triangles_overlap(const dvec2* a, const dvec2* b, double tolerance) {
  for (int side = 0; side < 2; ++side) {
    const dvec2* tri = side == 0 ? a : b;
    const dvec2* other = side == 0 ? b : a;
    for (int k = 0; k < 3; ++k) {
      const dvec2 p = tri[k];
      const dvec2 e = tri[(k + 1) % 3] - p;
      double nearest = kInf;  // the other triangle's least outward distance × |e|
      for (int j = 0; j < 3; ++j) nearest = std::min(nearest, -cross2(e, other[j] - p));
      if (nearest >= -tolerance * glm::length(e)) return false;
    }
  }
  return true;
}

// True when the triangles `order` (local numbers into `corners`) all keep their orientation
// and no two overlap.
bool is_injective(std::span<const uint32_t> order, const std::vector<dvec2>& corners,
                  double tolerance) {
  const size_t m = order.size();
  dvec2 lo(kInf), hi(-kInf);
  // Slivers narrower than the tolerance (needles whose normal is float noise; the loader
  // keeps them) cover nothing: their orientation and overlaps are not judged.
  std::vector<uint8_t> sliver(corners.size() / 3, 0);
  for (uint32_t i : order) {
    const dvec2* c = &corners[3 * i];
    const double twice_area = cross2(c[1] - c[0], c[2] - c[0]);
    const double longest = std::max(glm::length(c[1] - c[0]),
                                    std::max(glm::length(c[2] - c[1]), glm::length(c[0] - c[2])));
    if (twice_area < -tolerance * longest) return false;  // flipped
    sliver[i] = twice_area <= tolerance * longest;
    for (int k = 0; k < 3; ++k) {
      lo = glm::min(lo, c[k]);
      hi = glm::max(hi, c[k]);
    }
  }
  if (m <= 1) return true;
  auto bbox = [&](uint32_t i, dvec2& a, dvec2& b) {
    const dvec2* c = &corners[3 * i];
    a = glm::min(c[0], glm::min(c[1], c[2]));
    b = glm::max(c[0], glm::max(c[1], c[2]));
  };
  auto boxes_overlap = [&](uint32_t i, uint32_t j) {
    if (sliver[i] || sliver[j]) return false;
    dvec2 a0, a1, b0, b1;
    bbox(i, a0, a1);
    bbox(j, b0, b1);
    return a0.x < b1.x - tolerance && b0.x < a1.x - tolerance && a0.y < b1.y - tolerance &&
           b0.y < a1.y - tolerance;
  };
  if (m <= kBruteForceOverlap) {
    for (size_t p = 0; p < m; ++p)
      for (size_t q = p + 1; q < m; ++q)
        if (boxes_overlap(order[p], order[q]) &&
            triangles_overlap(&corners[3 * order[p]], &corners[3 * order[q]], tolerance))
          return false;
    return true;
  }
  // Uniform grid of about m cells over the chart; each pair is tested once, in the cell that
  // holds the lower corner of the intersection of their boxes.
  const dvec2 extent = glm::max(hi - lo, dvec2(1e-300));
  const double cell = std::sqrt(extent.x * extent.y / double(m));
  const int gx = std::clamp(int(std::ceil(extent.x / cell)), 1, 4096);
  const int gy = std::clamp(int(std::ceil(extent.y / cell)), 1, 4096);
  auto cell_x = [&](double x) { return std::clamp(int((x - lo.x) / extent.x * gx), 0, gx - 1); };
  auto cell_y = [&](double y) { return std::clamp(int((y - lo.y) / extent.y * gy), 0, gy - 1); };
  // Counting sort of the triangles into cells: count, prefix sums, fill.
  std::vector<uint32_t> begin(size_t(gx) * gy + 1, 0);
  std::vector<uint32_t> fill, items;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      for (size_t c = 1; c < begin.size(); ++c) begin[c] += begin[c - 1];
      fill.assign(begin.begin(), begin.end() - 1);
      items.resize(begin.back());
    }
    for (uint32_t i : order) {
      dvec2 a, b;
      bbox(i, a, b);
      for (int y = cell_y(a.y); y <= cell_y(b.y); ++y)
        for (int x = cell_x(a.x); x <= cell_x(b.x); ++x) {
          const size_t c = size_t(y) * gx + x;
          if (pass == 0)
            ++begin[c + 1];
          else
            items[fill[c]++] = i;
        }
    }
  }
  for (int y = 0; y < gy; ++y)
    for (int x = 0; x < gx; ++x) {
      const size_t c = size_t(y) * gx + x;
      for (uint32_t p = begin[c]; p < begin[c + 1]; ++p)
        for (uint32_t q = p + 1; q < begin[c + 1]; ++q) {
          const uint32_t i = items[p], j = items[q];
          if (!boxes_overlap(i, j)) continue;
          dvec2 a0, a1, b0, b1;
          bbox(i, a0, a1);
          bbox(j, b0, b1);
          if (cell_x(std::max(a0.x, b0.x)) != x || cell_y(std::max(a0.y, b0.y)) != y) continue;
          if (triangles_overlap(&corners[3 * i], &corners[3 * j], tolerance)) return false;
        }
    }
  return true;
}

// Counter-clockwise convex hull (Andrew's monotone chain), collinear points dropped.
std::vector<dvec2> convex_hull(std::vector<dvec2> points) {
  std::sort(points.begin(), points.end(),
            [](const dvec2& a, const dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<dvec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Unit direction of the x axis of the minimal-area bounding rectangle: one of the hull's
// edge directions (Freeman & Shapira 1975), found with rotating calipers in O(h).
dvec2 min_area_direction(const std::vector<dvec2>& hull) {
  const size_t h = hull.size();
  if (h < 3) return dvec2(1.0, 0.0);
  auto edge_dir = [&](size_t i) { return glm::normalize(hull[(i + 1) % h] - hull[i]); };
  auto along = [&](size_t i, const dvec2& u) { return glm::dot(hull[i % h], u); };
  auto across = [&](size_t i, const dvec2& u) { return cross2(u, hull[i % h]); };
  // For edge i (direction u), the hull lies left of it: `across` is smallest on the edge.
  // Pointers to the largest `along`, the largest `across`, and the smallest `along` only move
  // forward as u turns counter-clockwise.
  size_t far_along = 0, far_across = 0, near_along = 0;
  double best_area = kInf;
  dvec2 best(1.0, 0.0);
  for (size_t i = 0; i < h; ++i) {
    const dvec2 u = edge_dir(i);
    if (i == 0) {
      for (size_t j = 1; j < h; ++j) {
        if (along(j, u) > along(far_along, u)) far_along = j;
        if (across(j, u) > across(far_across, u)) far_across = j;
        if (along(j, u) < along(near_along, u)) near_along = j;
      }
    } else {
      for (size_t s = 0; s < h && along(far_along + 1, u) > along(far_along, u); ++s) ++far_along;
      for (size_t s = 0; s < h && across(far_across + 1, u) > across(far_across, u); ++s)
        ++far_across;
      for (size_t s = 0; s < h && along(near_along + 1, u) < along(near_along, u); ++s)
        ++near_along;
    }
    const double width = along(far_along, u) - along(near_along, u);
    const double height = across(far_across, u) - across(i, u);
    if (width * height < best_area) {
      best_area = width * height;
      best = u;
    }
  }
  return best;
}

// Rotates the corners to the minimal-area rectangle, lying, minimum at the origin.
Chart finish_chart(int mesh_index, std::vector<uint32_t> triangles, std::vector<dvec2> corners) {
  const dvec2 u = min_area_direction(convex_hull(corners));
  const dvec2 v(-u.y, u.x);  // (u, v) is a proper rotation: orientation is kept
  dvec2 lo(kInf), hi(-kInf);
  for (dvec2& c : corners) {
    c = dvec2(glm::dot(c, u), glm::dot(c, v));
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  const bool stand_up = hi.y - lo.y > hi.x - lo.x;
  for (dvec2& c : corners) {
    c -= lo;
    if (stand_up) c = dvec2(c.y, (hi.x - lo.x) - c.x);  // a quarter turn clockwise
  }
  Chart chart;
  chart.mesh = mesh_index;
  chart.triangles = std::move(triangles);
  chart.corners = std::move(corners);
  chart.size = stand_up ? dvec2(hi.y - lo.y, hi.x - lo.x) : hi - lo;
  for (size_t i = 0; i < chart.triangles.size(); ++i) {
    const dvec2* c = &chart.corners[3 * i];
    chart.area += 0.5 * cross2(c[1] - c[0], c[2] - c[0]);
  }
  return chart;
}

// Region growing: seeds in order of decreasing area; a seed takes every edge-connected
// triangle whose normal lies within the angle of the seed's normal.
std::vector<Region> grow_regions(const MeshGeometry& g, double cos_max) {
  const size_t n = g.triangle_count();
  std::vector<uint32_t> seeds;
  for (uint32_t t = 0; t < n; ++t)
    if (!g.degenerate[t]) seeds.push_back(t);
  std::stable_sort(seeds.begin(), seeds.end(),
                   [&](uint32_t a, uint32_t b) { return g.area[a] > g.area[b]; });
  std::vector<uint8_t> taken(n, 0);
  std::vector<Region> regions;
  for (uint32_t seed : seeds) {
    if (taken[seed]) continue;
    Region r;
    r.triangles.push_back(seed);
    taken[seed] = 1;
    const dvec3 axis = g.normal[seed];
    for (size_t head = 0; head < r.triangles.size(); ++head)
      for (uint32_t nb : g.neighbours(r.triangles[head])) {
        if (taken[nb] || glm::dot(g.normal[nb], axis) < cos_max) continue;
        taken[nb] = 1;
        r.triangles.push_back(nb);
      }
    r.axis = choose_axis(g, r.triangles, axis);
    regions.push_back(std::move(r));
  }
  return regions;
}

// Splits `triangles` (a subset of the mesh) into edge-connected parts, each in breadth-first
// order from its earliest member.
std::vector<std::vector<uint32_t>> connected_parts(const MeshGeometry& g,
                                                   std::span<const uint32_t> triangles,
                                                   std::vector<uint32_t>& mark, uint32_t& stamp) {
  ++stamp;
  const uint32_t member = stamp, visited = ++stamp;
  for (uint32_t t : triangles) mark[t] = member;
  std::vector<std::vector<uint32_t>> parts;
  for (uint32_t start : triangles) {
    if (mark[start] != member) continue;
    std::vector<uint32_t> part{start};
    mark[start] = visited;
    for (size_t head = 0; head < part.size(); ++head)
      for (uint32_t nb : g.neighbours(part[head]))
        if (mark[nb] == member) {
          mark[nb] = visited;
          part.push_back(nb);
        }
    parts.push_back(std::move(part));
  }
  return parts;
}

// Charts of one mesh in world space. A region whose projection overlaps itself (a spiral
// ramp, coincident duplicate faces) keeps its longest breadth-first prefix that is injective
// (injectivity is monotone in the prefix, so binary search finds it); the rest is split into
// connected parts that are charted again. One triangle alone is always injective, so this
// ends. Zero-area triangles share one chart of one texel per mesh (all corners at its centre).
std::vector<Chart> chart_mesh(const Mesh& mesh, size_t mesh_index, const mat4& transform,
                              double cos_max, double waste_limit) {
  const MeshGeometry g = mesh_geometry(mesh, mesh_index, transform);
  const int index = int(mesh_index);
  std::vector<Region> work = grow_regions(g, cos_max);
  std::vector<Chart> charts;
  std::vector<uint32_t> mark(g.triangle_count(), 0);
  uint32_t stamp = 0;
  auto split_into_work = [&](std::span<const uint32_t> triangles, const dvec3& axis) {
    for (std::vector<uint32_t>& part : connected_parts(g, triangles, mark, stamp)) {
      Region r;
      r.axis = choose_axis(g, part, axis);
      r.triangles = std::move(part);
      work.push_back(std::move(r));
    }
  };
  // A sparse chart (a thin ring such as the top of a wall running round a floor plan) wastes
  // most of its rectangle; it is cut in two across its long side, at the median triangle,
  // until the pieces fill their rectangles or waste little.
  auto emit = [&](Region&& region, std::vector<dvec2>&& corners) {
    const dvec3 axis = region.axis;
    Chart chart = finish_chart(index, std::move(region.triangles), std::move(corners));
    const double rectangle = chart.size.x * chart.size.y;
    if (chart.triangles.size() < 2 || chart.area >= kMinChartFill * rectangle ||
        rectangle - chart.area <= waste_limit) {
      charts.push_back(std::move(chart));
      return;
    }
    std::vector<std::pair<double, uint32_t>> along(chart.triangles.size());
    for (size_t i = 0; i < chart.triangles.size(); ++i) {
      const dvec2* c = &chart.corners[3 * i];
      along[i] = {c[0].x + c[1].x + c[2].x, chart.triangles[i]};
    }
    std::sort(along.begin(), along.end());
    std::vector<uint32_t> halves(along.size());
    for (size_t i = 0; i < along.size(); ++i) halves[i] = along[i].second;
    const size_t half = halves.size() / 2;
    split_into_work(std::span(halves).first(half), axis);
    split_into_work(std::span(halves).subspan(half), axis);
  };
  for (size_t w = 0; w < work.size(); ++w) {
    Region region = std::move(work[w]);
    std::vector<dvec2> corners = project(mesh, g, region);
    std::vector<uint32_t> local(region.triangles.size());
    std::iota(local.begin(), local.end(), 0u);
    dvec2 lo(kInf), hi(-kInf);
    for (const dvec2& c : corners) {
      lo = glm::min(lo, c);
      hi = glm::max(hi, c);
    }
    // Shared vertices project to identical coordinates, so shared edges touch exactly; the
    // tolerance only absorbs double rounding. (Seams welded from slightly different positions
    // that overlap are split: correctness first, and exporters rarely produce them.)
    const double tolerance = 1e-9 * glm::length(hi - lo);
    if (is_injective(local, corners, tolerance)) {
      emit(std::move(region), std::move(corners));
      continue;
    }
    size_t good = 1, bad = local.size();  // prefix lengths: good is injective, bad is not
    while (bad - good > 1) {
      const size_t mid = good + (bad - good) / 2;
      (is_injective(std::span(local).first(mid), corners, tolerance) ? good : bad) = mid;
    }
    split_into_work(std::span(region.triangles).subspan(good), region.axis);
    region.triangles.resize(good);
    corners.resize(3 * good);
    emit(std::move(region), std::move(corners));
  }
  Chart points;
  for (uint32_t t = 0; t < g.triangle_count(); ++t)
    if (g.degenerate[t]) points.triangles.push_back(t);
  if (!points.triangles.empty()) {
    points.mesh = index;
    points.corners.assign(3 * points.triangles.size(), dvec2(0.0));
    charts.push_back(std::move(points));
  }
  return charts;
}

// ---------------------------------------------------------------------------------------------
// Packing.

// Texel cells a chart of `size` metres reserves at texel size `s`: every texel its triangles
// can touch once it is centred in them, with kCellMargin to spare on each side.
ivec2 cells_of(const dvec2& size, double s) {
  const dvec2 t = size / s + 2.0 * kCellMargin;
  return ivec2(int(std::ceil(t.x)), int(std::ceil(t.y)));
}

// Skyline bottom-left packer: rectangles sorted by decreasing height; each goes where its
// top ends lowest (then leftmost). The skyline is a list of segments covering [0, width).
class SkylinePacker {
 public:
  SkylinePacker(int width, int height) : width_(width), height_(height) {
    segments_.push_back({0, 0, width});
  }

  // Places a w×h rectangle; returns false when it fits nowhere.
  bool place(int w, int h, ivec2& where) {
    if (w > width_ || h > height_) return false;
    int best_top = std::numeric_limits<int>::max(), best_i = -1, best_y = 0;
    // Sliding window [i, j) of segments under the rectangle, with a monotone queue of their
    // heights, so each candidate costs O(1) amortized.
    window_.clear();
    size_t front = 0, j = 0;
    for (size_t i = 0; i < segments_.size(); ++i) {
      const int x = segments_[i].x;
      if (x + w > width_) break;
      while (front < window_.size() && window_[front] < i) ++front;
      while (j < segments_.size() && (j == i || segments_[j - 1].x + segments_[j - 1].w < x + w)) {
        while (window_.size() > front && segments_[window_.back()].y <= segments_[j].y)
          window_.pop_back();
        window_.push_back(j);
        ++j;
      }
      while (front < window_.size() && window_[front] < i) ++front;
      const int y = segments_[window_[front]].y;
      if (y + h <= height_ && y + h < best_top) {
        best_top = y + h;
        best_i = int(i);
        best_y = y;
      }
    }
    if (best_i < 0) return false;
    where = ivec2(segments_[best_i].x, best_y);
    insert(size_t(best_i), w, best_y + h);
    return true;
  }

 private:
  struct Segment {
    int x, y, w;
  };

  void insert(size_t i, int w, int top) {
    const int x0 = segments_[i].x, x1 = x0 + w;
    size_t end = i;  // first segment not fully covered
    while (end < segments_.size() && segments_[end].x + segments_[end].w <= x1) ++end;
    if (end < segments_.size() && segments_[end].x < x1) {
      segments_[end].w -= x1 - segments_[end].x;
      segments_[end].x = x1;
    }
    segments_.erase(segments_.begin() + i, segments_.begin() + end);
    segments_.insert(segments_.begin() + i, Segment{x0, top, w});
    if (i + 1 < segments_.size() && segments_[i + 1].y == top) {
      segments_[i].w += segments_[i + 1].w;
      segments_.erase(segments_.begin() + i + 1);
    }
    if (i > 0 && segments_[i - 1].y == top) {
      segments_[i - 1].w += segments_[i].w;
      segments_.erase(segments_.begin() + i);
    }
  }

  int width_, height_;
  std::vector<Segment> segments_;
  std::vector<size_t> window_;
};

// Where a chart sits in its cells: centred, so the margin is at least kCellMargin per side.
dvec2 offset_in_cells(const Chart& chart, const ivec2& cells, double s) {
  return 0.5 * (dvec2(cells) - chart.size / s);
}

// Free space inside a host chart's cells, as disjoint rectangles (x, y, width, height, in
// cells) that lie more than `padding` cells from every texel the chart touches. The chart's
// conservative coverage (every texel a triangle meets, boundaries included) is marked on a
// grid of blocks of k×k cells (k = 1 up to kMaxHostBlocks cells; coarser blocks only lose
// some free space), grown by ceil(padding / k) blocks; then the largest free rectangles are
// taken one by one (a slanted edge leaves a staircase that row-by-row cutting would slice
// into useless one-row strips).
std::vector<glm::ivec4> free_rectangles(const Chart& chart, const ivec2& cells, double s,
                                        int padding) {
  const int k = std::max(1, int(std::ceil(std::sqrt(double(cells.x) * cells.y / kMaxHostBlocks))));
  const int w = (cells.x + k - 1) / k, h = (cells.y + k - 1) / k;
  std::vector<uint8_t> used(size_t(w) * h, 0);
  const dvec2 offset = offset_in_cells(chart, cells, s);
  for (size_t i = 0; i < chart.triangles.size(); ++i) {
    dvec2 p[3];
    for (int j = 0; j < 3; ++j) p[j] = offset + chart.corners[3 * i + j] / s;
    const double y_lo = std::min(p[0].y, std::min(p[1].y, p[2].y));
    const double y_hi = std::max(p[0].y, std::max(p[1].y, p[2].y));
    // Row by row of cells: the triangle's x-range within the band [y, y + 1] comes from its
    // vertices inside the band and its edges' crossings of the band's two lines.
    for (int y = std::max(0, int(std::floor(y_lo)));
         y <= std::min(cells.y - 1, int(std::floor(y_hi))); ++y) {
      double x_lo = kInf, x_hi = -kInf;
      for (int j = 0; j < 3; ++j) {
        const dvec2 a = p[j], b = p[(j + 1) % 3];
        if (a.y >= y && a.y <= y + 1) {
          x_lo = std::min(x_lo, a.x);
          x_hi = std::max(x_hi, a.x);
        }
        for (const double line : {double(y), double(y + 1)})
          if ((a.y - line) * (b.y - line) < 0.0) {
            const double x = a.x + (b.x - a.x) * (line - a.y) / (b.y - a.y);
            x_lo = std::min(x_lo, x);
            x_hi = std::max(x_hi, x);
          }
      }
      if (x_lo > x_hi) continue;
      const int x0 = std::max(0, int(std::floor(x_lo))) / k;
      const int x1 = std::min(cells.x - 1, int(std::floor(x_hi))) / k;
      std::fill(used.begin() + size_t(y / k) * w + x0, used.begin() + size_t(y / k) * w + x1 + 1,
                uint8_t(1));
    }
  }
  // Grow by r blocks (Chebyshev): running counts along rows, then along columns.
  const int r = (padding + k - 1) / k;
  std::vector<uint8_t> grown(used.size(), 0);
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = &used[size_t(y) * w];
    int count = 0;
    for (int x = 0; x < std::min(w, r); ++x) count += row[x];
    for (int x = 0; x < w; ++x) {
      if (x + r < w) count += row[x + r];
      if (x - r - 1 >= 0) count -= row[x - r - 1];
      grown[size_t(y) * w + x] = count > 0;
    }
  }
  for (int x = 0; x < w; ++x) {
    int count = 0;
    for (int y = 0; y < std::min(h, r); ++y) count += grown[size_t(y) * w + x];
    for (int y = 0; y < h; ++y) {
      if (y + r < h) count += grown[size_t(y + r) * w + x];
      if (y - r - 1 >= 0) count -= grown[size_t(y - r - 1) * w + x];
      used[size_t(y) * w + x] = count > 0;
    }
  }
  // The largest free rectangle (histogram of free runs down each column, a stack per row),
  // taken and marked, up to kMaxHolesPerHost times while one can hold a one-cell chart.
  std::vector<glm::ivec4> rects;
  std::vector<int> run(w), stack;
  for (int hole = 0; hole < kMaxHolesPerHost; ++hole) {
    std::fill(run.begin(), run.end(), 0);
    int64_t best_area = 0;
    glm::ivec4 best(0);  // in blocks: x, y, width, height
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) run[x] = used[size_t(y) * w + x] ? 0 : run[x] + 1;
      stack.clear();
      for (int x = 0; x <= w; ++x) {
        const int height = x < w ? run[x] : 0;
        while (!stack.empty() && run[stack.back()] >= height) {
          const int top = run[stack.back()];
          stack.pop_back();
          const int left = stack.empty() ? 0 : stack.back() + 1;
          const int64_t area = int64_t(top) * (x - left);
          if (area > best_area) {
            best_area = area;
            best = {left, y - top + 1, x - left, top};
          }
        }
        stack.push_back(x);
      }
    }
    if (best_area == 0) break;
    // In cells, clipped to the chart's cells (the last block may reach past them).
    const int cx = best.x * k, cy = best.y * k;
    const int cw = std::min((best.x + best.z) * k, cells.x) - cx;
    const int ch = std::min((best.y + best.w) * k, cells.y) - cy;
    if (cw <= padding || ch <= padding) break;
    rects.push_back({cx, cy, cw, ch});
    for (int y = best.y; y < best.y + best.w; ++y)
      std::fill(used.begin() + size_t(y) * w + best.x,
                used.begin() + size_t(y) * w + best.x + best.z, uint8_t(1));
  }
  return rects;
}

// Packs every chart at texel size `s`: origins[c] is the first texel of chart c's cells.
// Each item reserves its cells plus `padding` texels on its high sides, in a bin that starts
// and ends `padding` texels inside the atlas border, so cells are ≥ padding apart everywhere.
// Big sparse charts (floor plans) host smaller ones: the free rectangles of their padded
// footprint become bins of their own (an item there also keeps `padding` free on its high
// sides, so items of two disjoint free rectangles stay apart), tried before the skyline.
bool pack_charts(const std::vector<Chart>& charts, double s, int resolution, int padding,
                 std::vector<ivec2>* origins) {
  const int bin = resolution - 2 * padding;
  struct Item {
    ivec2 size;  // cells + padding
    uint32_t chart;
  };
  std::vector<Item> items(charts.size());
  double area = 0.0;  // a lower bound of the area needed (holes excluded)
  for (size_t c = 0; c < charts.size(); ++c) {
    const dvec2 texels = charts[c].size / s;
    if (texels.x > resolution || texels.y > resolution) return false;
    items[c] = {cells_of(charts[c].size, s) + padding, uint32_t(c)};
    area += std::min(1.0, charts[c].fill()) * items[c].size.x * items[c].size.y;
  }
  if (area > double(bin + padding) * (bin + padding)) return false;
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.size.y != b.size.y) return a.size.y > b.size.y;
    if (a.size.x != b.size.x) return a.size.x > b.size.x;
    return a.chart < b.chart;
  });
  SkylinePacker packer(bin + padding, bin + padding);
  struct HoleBin {
    ivec2 origin;
    SkylinePacker packer;
    // The smallest item that did not fit: anything as wide and as tall cannot fit later
    // either (bins only fill up), so it is not tried.
    ivec2 failed{std::numeric_limits<int>::max()};
  };
  std::vector<HoleBin> holes;
  if (origins) origins->assign(charts.size(), ivec2(0));
  for (const Item& item : items) {
    ivec2 where, origin;
    bool placed = false;
    for (HoleBin& hole : holes) {
      if (item.size.x >= hole.failed.x && item.size.y >= hole.failed.y) continue;
      if (hole.packer.place(item.size.x, item.size.y, where)) {
        origin = hole.origin + where;
        placed = true;
        break;
      }
      if (item.size.x <= hole.failed.x && item.size.y <= hole.failed.y) hole.failed = item.size;
    }
    if (!placed) {
      if (!packer.place(item.size.x, item.size.y, where)) return false;
      origin = where + padding;
    }
    if (origins) (*origins)[item.chart] = origin;
    const Chart& chart = charts[item.chart];
    const ivec2 cells = item.size - padding;
    if (chart.fill() < kHostFill && cells.x * cells.y >= kMinHostCells)
      for (const glm::ivec4& r : free_rectangles(chart, cells, s, padding))
        holes.push_back({origin + ivec2(r.x, r.y), SkylinePacker(r.z, r.w)});
  }
  return true;
}

// The finest texel size that packs, by bisection on log s between the area bound (nothing
// finer can fit) and the size at which every chart is one cell. Returns 0 if even that fails.
double finest_search(const std::vector<Chart>& charts, int resolution, int padding) {
  double area = 0.0, largest = 0.0;  // the triangles' area: no packing needs less
  for (const Chart& c : charts) {
    area += c.area;
    largest = std::max(largest, std::max(c.size.x, c.size.y));
  }
  // At this size every chart spans less than half a texel: one cell each.
  const double coarse = largest > 0.0 ? 2.0 * largest : 1.0;
  if (!pack_charts(charts, coarse, resolution, padding, nullptr)) return 0.0;
  const double span = double(resolution - 2 * padding);  // cells lie within it
  double lo = std::max(std::sqrt(area) / span, largest / span);
  if (!(lo > 0.0) || lo >= coarse) return coarse;
  if (pack_charts(charts, lo, resolution, padding, nullptr)) return lo;
  // The answer is usually within tens of percent of the area bound: bracket it in steps of
  // 25% before bisecting (fewer packings than bisecting from `coarse`).
  double hi = lo;
  do {
    hi = std::min(hi * 1.25, coarse);
    if (pack_charts(charts, hi, resolution, padding, nullptr)) break;
    lo = hi;
  } while (hi < coarse);
  while (hi / lo > 1.0 + kSearchRelPrecision) {
    const double mid = std::sqrt(lo * hi);
    (pack_charts(charts, mid, resolution, padding, nullptr) ? hi : lo) = mid;
  }
  return hi;
}

// finest_search rounded up to a float that packs, so Atlas::texel_size given back as
// AtlasOptions::texel_size reproduces the same atlas. Returns 0 if nothing fits.
float finest_texel_size(const std::vector<Chart>& charts, int resolution, int padding) {
  const double s = finest_search(charts, resolution, padding);
  if (!(s > 0.0)) return 0.0f;
  float f = float(s);
  if (double(f) < s) f = std::nextafter(f, kInf);
  // Packing is not strictly monotone in s; a few float steps up always find a size that fits
  // (s itself packed, and f is within one float step of it).
  for (int step = 0; step < 64; ++step, f = std::nextafter(f, kInf))
    if (pack_charts(charts, double(f), resolution, padding, nullptr)) return f;
  ILLUM_CHECK(false, "no float texel size near {} packs", s);
  return 0.0f;
}

// World-space area of a mesh's triangles (0 where indices are out of range: chart_mesh
// reports those).
double world_area(const Mesh& mesh, int instance, const Scene& scene) {
  const glm::dmat4 m(scene.instances[instance].transform);
  double area = 0.0;
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    dvec3 p[3];
    bool valid = true;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.indices[3 * t + k];
      valid = valid && v < mesh.positions.size();
      if (valid) p[k] = dvec3(m * glm::dvec4(dvec3(mesh.positions[v]), 1.0));
    }
    if (valid) area += 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
  }
  return std::isfinite(area) ? area : 0.0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

void make_meshes_unique(Scene& scene) {
  std::vector<uint8_t> used(scene.meshes.size(), 0);
  for (Instance& instance : scene.instances) {
    if (instance.mesh < 0 || size_t(instance.mesh) >= scene.meshes.size())
      throw Error(fmt::format("instance '{}' refers to mesh {}, but the scene has {}",
                              instance.name, instance.mesh, scene.meshes.size()));
    if (!used[instance.mesh]) {
      used[instance.mesh] = 1;
      continue;
    }
    Mesh copy = scene.meshes[instance.mesh];
    scene.meshes.push_back(std::move(copy));
    used.push_back(1);
    instance.mesh = int(scene.meshes.size() - 1);
  }
}

Atlas build_atlas(const Scene& scene, const AtlasOptions& options) {
  validate_options(options);
  const auto start = std::chrono::steady_clock::now();
  // The one instance of each mesh (−1: none).
  std::vector<int> instance_of(scene.meshes.size(), -1);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    if (instance.mesh < 0 || size_t(instance.mesh) >= scene.meshes.size())
      throw Error(fmt::format("atlas: instance '{}' refers to mesh {}, but the scene has {}",
                              instance.name, instance.mesh, scene.meshes.size()));
    int& owner = instance_of[instance.mesh];
    if (owner >= 0)
      throw Error(
          fmt::format("atlas: {} is used by instances '{}' and '{}'; light-maps need one mesh per "
                      "instance (call make_meshes_unique first)",
                      mesh_label(scene.meshes[instance.mesh], instance.mesh),
                      scene.instances[owner].name, instance.name));
    owner = int(i);
  }

  const double cos_max = std::cos(double(options.max_chart_angle) * std::numbers::pi / 180.0);
  std::vector<std::vector<Chart>> per_mesh(scene.meshes.size());
  std::vector<std::exception_ptr> failure(scene.meshes.size());
  std::vector<double> mesh_area(scene.meshes.size(), 0.0);
  tbb::parallel_for(size_t(0), scene.meshes.size(), [&](size_t m) {
    if (instance_of[m] >= 0) mesh_area[m] = world_area(scene.meshes[m], instance_of[m], scene);
  });
  const double waste_limit =
      kMaxChartWaste * std::accumulate(mesh_area.begin(), mesh_area.end(), 0.0);
  tbb::parallel_for(size_t(0), scene.meshes.size(), [&](size_t m) {
    if (instance_of[m] < 0) return;
    try {
      per_mesh[m] = chart_mesh(scene.meshes[m], m, scene.instances[instance_of[m]].transform,
                               cos_max, waste_limit);
    } catch (...) {
      failure[m] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : failure)
    if (e) std::rethrow_exception(e);
  std::vector<Chart> charts;
  for (std::vector<Chart>& list : per_mesh)
    for (Chart& c : list) charts.push_back(std::move(c));

  const int resolution = options.resolution;
  double s = options.texel_size;
  std::vector<ivec2> origins;
  if (!charts.empty()) {
    if (s > 0.0) {
      if (!pack_charts(charts, s, resolution, options.padding, &origins)) {
        const float finest = finest_texel_size(charts, resolution, options.padding);
        throw Error(
            finest > 0.0
                ? fmt::format("atlas: {} charts do not fit a {}×{} atlas at texel_size {} m "
                              "(padding {}); the finest that fits is about {:.4g} m",
                              charts.size(), resolution, resolution, options.texel_size,
                              options.padding, finest)
                : fmt::format("atlas: {} charts do not fit a {}×{} atlas at texel_size {} m "
                              "(padding {}), not even at one texel each",
                              charts.size(), resolution, resolution, options.texel_size,
                              options.padding));
      }
    } else {
      s = double(finest_texel_size(charts, resolution, options.padding));
      if (!(s > 0.0))
        throw Error(fmt::format(
            "atlas: {} charts do not fit a {}×{} atlas (padding {}) at any texel_size, not even "
            "at one texel each",
            charts.size(), resolution, resolution, options.padding));
      const bool packed = pack_charts(charts, s, resolution, options.padding, &origins);
      ILLUM_CHECK(packed, "the texel size found by the search must pack");
    }
  }

  Atlas atlas;
  atlas.width = atlas.height = resolution;
  atlas.texel_size = float(s);
  atlas.chart_count = int(charts.size());
  atlas.charts.resize(charts.size());
  // Per triangle: its chart and its corners' uv1.
  std::vector<std::vector<uint32_t>> chart_of(scene.meshes.size());
  std::vector<std::vector<vec2>> corner_uv(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    chart_of[m].assign(scene.meshes[m].triangle_count(), kNoChart);
    corner_uv[m].assign(scene.meshes[m].indices.size(), vec2(0.0f));
  }
  const double inv_resolution = 1.0 / resolution;
  for (size_t c = 0; c < charts.size(); ++c) {
    const Chart& chart = charts[c];
    const ivec2 cells = cells_of(chart.size, s);
    atlas.charts[c] = {chart.mesh, origins[c].x, origins[c].y, cells.x, cells.y};
    const dvec2 offset = dvec2(origins[c]) + offset_in_cells(chart, cells, s);
    for (size_t i = 0; i < chart.triangles.size(); ++i) {
      const uint32_t t = chart.triangles[i];
      chart_of[chart.mesh][t] = uint32_t(c);
      for (int k = 0; k < 3; ++k)
        corner_uv[chart.mesh][3 * t + k] =
            vec2((offset + chart.corners[3 * i + k] / s) * inv_resolution);
    }
  }

  // Seam vertices are split: a new vertex per (source vertex, chart), numbered in order of
  // first use by triangle and corner.
  atlas.meshes.resize(scene.meshes.size());
  tbb::parallel_for(size_t(0), scene.meshes.size(), [&](size_t m) {
    const Mesh& mesh = scene.meshes[m];
    MeshLayout& layout = atlas.meshes[m];
    layout.source_vertex_count = uint32_t(mesh.positions.size());
    layout.triangle_chart = std::move(chart_of[m]);
    layout.indices.resize(mesh.indices.size());
    std::unordered_map<uint64_t, uint32_t> vertex_of;
    vertex_of.reserve(mesh.indices.size());
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
      const uint32_t source = mesh.indices[i];
      const uint64_t key = (uint64_t(source) << 32) | layout.triangle_chart[i / 3];
      auto [it, inserted] = vertex_of.try_emplace(key, uint32_t(layout.source_vertex.size()));
      if (inserted) {
        layout.source_vertex.push_back(source);
        layout.uv1.push_back(corner_uv[m][i]);
      }
      layout.indices[i] = it->second;
    }
  });

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  log::debug("atlas: {} charts in {}×{} at {:.4g} m per texel ({:.2f} s)", charts.size(),
             resolution, resolution, s, seconds);
  return atlas;
}

void apply_atlas(Scene& scene, const Atlas& atlas) {
  if (atlas.meshes.size() != scene.meshes.size())
    throw Error(fmt::format("apply_atlas: the atlas has {} meshes, the scene '{}' has {}",
                            atlas.meshes.size(), scene.name, scene.meshes.size()));
  // Everything is checked and built before the scene changes, so a refused atlas leaves the
  // scene as it was.
  std::vector<Mesh> rebuilt(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const MeshLayout& layout = atlas.meshes[m];
    const std::string label = mesh_label(mesh, m);
    const size_t old_count = mesh.positions.size();
    if (layout.source_vertex_count != old_count)
      throw Error(fmt::format(
          "apply_atlas: the atlas does not match {}: it was made for {} vertices, the mesh "
          "has {}",
          label, layout.source_vertex_count, old_count));
    if (layout.indices.size() != mesh.indices.size())
      throw Error(fmt::format(
          "apply_atlas: the atlas does not match {}: it has {} triangles, the mesh has {}", label,
          layout.indices.size() / 3, mesh.triangle_count()));
    if (layout.uv1.size() != layout.source_vertex.size())
      throw Error(fmt::format("apply_atlas: the atlas layout of {} has {} uv1 for {} vertices",
                              label, layout.uv1.size(), layout.source_vertex.size()));
    for (uint32_t v : layout.source_vertex)
      if (v >= old_count)
        throw Error(fmt::format("apply_atlas: the atlas layout of {} refers to vertex {} of {}",
                                label, v, old_count));
    for (size_t i = 0; i < layout.indices.size(); ++i) {
      const uint32_t v = layout.indices[i];
      if (v >= layout.source_vertex.size())
        throw Error(fmt::format("apply_atlas: the atlas layout of {} uses vertex {} of {}", label,
                                v, layout.source_vertex.size()));
      if (layout.source_vertex[v] != mesh.indices[i])
        throw Error(fmt::format(
            "apply_atlas: the atlas does not match {}: triangle {} corner {} comes from vertex "
            "{}, the mesh uses {}",
            label, i / 3, i % 3, layout.source_vertex[v], mesh.indices[i]));
    }
    for (const vec2& uv : layout.uv1)
      if (!(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f))
        throw Error(
            fmt::format("apply_atlas: the atlas layout of {} has uv1 ({}, {}) outside "
                        "[0,1]",
                        label, uv.x, uv.y));
    auto check_size = [&](size_t size, const char* what) {
      if (size != 0 && size != old_count)
        throw Error(
            fmt::format("apply_atlas: {} has {} {} for {} vertices", label, size, what, old_count));
    };
    check_size(mesh.normals.size(), "normals");
    check_size(mesh.tangents.size(), "tangents");
    check_size(mesh.uv0.size(), "uv0");

    Mesh& out = rebuilt[m];
    out.name = mesh.name;
    out.material = mesh.material;
    out.indices = layout.indices;
    out.uv1 = layout.uv1;
    auto gather = [&](const auto& from, auto& to) {
      if (from.empty()) return;
      to.resize(layout.source_vertex.size());
      for (size_t v = 0; v < layout.source_vertex.size(); ++v)
        to[v] = from[layout.source_vertex[v]];
    };
    gather(mesh.positions, out.positions);
    gather(mesh.normals, out.normals);
    gather(mesh.tangents, out.tangents);
    gather(mesh.uv0, out.uv0);
  }
  for (size_t m = 0; m < scene.meshes.size(); ++m) scene.meshes[m] = std::move(rebuilt[m]);
}

}  // namespace illum::atlas
