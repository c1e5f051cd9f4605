// Charts of one mesh: world-space geometry and welded adjacency, region growing, planar
// projection, injectivity repair, minimal-area rotation and the cut of sparse charts
// (README.md "How it is built", steps 1–7).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>

#include "illum/atlas/charts.h"
#include "illum/core/error.h"
#include "illum/scene/mesh_processing.h"

namespace illum::atlas::detail {

std::string mesh_label(const Mesh& mesh, size_t index) {
  return fmt::format("mesh '{}' (#{})", mesh.name, index);
}

namespace {

// Positions closer than this fraction of the mesh's world diagonal are one vertex for
// adjacency (loaders split vertices at normal/uv seams; exporters may round differently).
constexpr double kWeldRelTolerance = 1e-6;
// Charts with at most this many triangles are checked for overlaps pair by pair.
constexpr size_t kBruteForceOverlap = 16;
// A chart covering less than this fraction of its rectangle is split, when the space it
// wastes exceeds the caller's limit (rings, long thin L-shapes).
constexpr double kMinChartFill = 0.25;

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

}  // namespace

Chart chart_from_uv1(const Mesh& mesh, size_t mesh_index, const mat4& transform) {
  const glm::dmat4 m(transform);
  std::vector<uint32_t> triangles(mesh.triangle_count());
  std::iota(triangles.begin(), triangles.end(), 0u);
  std::vector<dvec2> corners(mesh.indices.size());
  double world = 0.0;
  for (size_t t = 0; t < triangles.size(); ++t) {
    dvec3 p[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.indices[3 * t + size_t(k)];
      corners[3 * t + size_t(k)] = dvec2(mesh.uv1[v]);
      p[k] = dvec3(m * glm::dvec4(dvec3(mesh.positions[v]), 1.0));
    }
    world += 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
  }
  Chart chart = finish_chart(int(mesh_index), std::move(triangles), std::move(corners));
  // Mirrored triangles are legitimate in a given UV1: its area is the sum of magnitudes.
  chart.area = 0.0;
  for (size_t i = 0; i < chart.triangles.size(); ++i) {
    const dvec2* c = &chart.corners[3 * i];
    chart.area += 0.5 * std::abs(cross2(c[1] - c[0], c[2] - c[0]));
  }
  scale_to_area(chart, world);
  return chart;
}

void scale_to_area(Chart& chart, double world_area) {
  if (!(chart.area > 0.0 && world_area > 0.0)) return;
  const double f = std::sqrt(world_area / chart.area);
  for (dvec2& c : chart.corners) c *= f;
  chart.size *= f;
  chart.area = world_area;
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
    double world = 0.0;
    for (uint32_t t : chart.triangles) world += g.area[t];
    scale_to_area(chart, world);
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

}  // namespace illum::atlas::detail
