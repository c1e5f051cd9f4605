#include "illum/atlas/uv1_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "illum/core/error.h"
#include "illum/scene/mesh_processing.h"

namespace illum::atlas {
namespace {

// Rounding of uv1 ∈ [0,1] stored as floats by another tool: shared corners written twice
// (seam vertices) may differ by a few ulps (6e-8 each); 1e-6 absorbs that and is 1/64 of a
// texel even at 16384².
constexpr double kTouchTolerance = 1e-6;

struct UvTriangle {
  glm::dvec2 c[3];  // counter-clockwise
  glm::dvec2 lo, hi;
  int mesh, triangle;
};

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// Interior overlap by separating axes (the six edge normals of two counter-clockwise
// triangles); touching within the tolerance is no overlap.
bool interiors_overlap(const UvTriangle& a, const UvTriangle& b) {
  for (int side = 0; side < 2; ++side) {
    const UvTriangle& tri = side == 0 ? a : b;
    const UvTriangle& other = side == 0 ? b : a;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 p = tri.c[k];
      const glm::dvec2 e = tri.c[(k + 1) % 3] - p;
      double deepest = std::numeric_limits<double>::infinity();  // least outward distance × |e|
      for (int j = 0; j < 3; ++j) deepest = std::min(deepest, -cross2(e, other.c[j] - p));
      if (deepest >= -kTouchTolerance * glm::length(e)) return false;
    }
  }
  return true;
}

// True when a uv1 triangle's area is below the touch tolerance (a needle or a point).
bool covers_nothing(const glm::dvec2 c[3]) {
  const double area2 = cross2(c[1] - c[0], c[2] - c[0]);
  const double longest =
      std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
  return std::abs(area2) <= kTouchTolerance * longest;
}

// The uv1 triangles of one light-mapped mesh, counter-clockwise; zero-area ones (which
// cover nothing) left out. Throws Error for a malformed mesh or a non-finite uv1.
void collect_triangles(const Mesh& mesh, int m, std::vector<UvTriangle>& tris) {
  if (mesh.uv1.size() != mesh.positions.size() || mesh.indices.size() % 3 != 0)
    throw Error(fmt::format("uv1 check: mesh '{}' has {} uv1 for {} vertices and {} indices",
                            mesh.name, mesh.uv1.size(), mesh.positions.size(),
                            mesh.indices.size()));
  for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
    UvTriangle u;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.indices[3 * t + size_t(k)];
      if (v >= mesh.uv1.size())
        throw Error(fmt::format("uv1 check: mesh '{}' has vertex index {} of {}", mesh.name, v,
                                mesh.uv1.size()));
      const vec2 uv = mesh.uv1[v];
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
        throw Error(
            fmt::format("uv1 check: mesh '{}' vertex {} has a non-finite uv1", mesh.name, v));
      u.c[k] = glm::dvec2(uv);
    }
    if (covers_nothing(u.c)) continue;
    if (cross2(u.c[1] - u.c[0], u.c[2] - u.c[0]) < 0.0) std::swap(u.c[1], u.c[2]);
    u.lo = glm::min(u.c[0], glm::min(u.c[1], u.c[2]));
    u.hi = glm::max(u.c[0], glm::max(u.c[1], u.c[2]));
    u.mesh = m;
    u.triangle = int(t);
    tris.push_back(u);
  }
}

std::optional<Uv1Overlap> first_overlap(const std::vector<UvTriangle>& tris) {
  if (tris.size() < 2) return std::nullopt;

  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (const UvTriangle& t : tris) {
    lo = glm::min(lo, t.lo);
    hi = glm::max(hi, t.hi);
  }
  const glm::dvec2 extent = glm::max(hi - lo, glm::dvec2(1e-300));
  const int side = std::clamp(int(std::ceil(std::sqrt(double(tris.size())))), 1, 2048);
  auto cell = [&](double v, double l, double e) {
    return std::clamp(int((v - l) / e * side), 0, side - 1);
  };
  std::vector<std::vector<uint32_t>> cells(size_t(side) * size_t(side));
  for (uint32_t i = 0; i < tris.size(); ++i)
    for (int y = cell(tris[i].lo.y, lo.y, extent.y); y <= cell(tris[i].hi.y, lo.y, extent.y); ++y)
      for (int x = cell(tris[i].lo.x, lo.x, extent.x); x <= cell(tris[i].hi.x, lo.x, extent.x); ++x)
        cells[size_t(y) * side + size_t(x)].push_back(i);

  std::optional<std::tuple<int, int, int, int>> first;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const std::vector<uint32_t>& items = cells[size_t(y) * side + size_t(x)];
      for (size_t p = 0; p < items.size(); ++p)
        for (size_t q = p + 1; q < items.size(); ++q) {
          const UvTriangle& a = tris[items[p]];
          const UvTriangle& b = tris[items[q]];
          const glm::dvec2 both_lo = glm::max(a.lo, b.lo), both_hi = glm::min(a.hi, b.hi);
          if (both_lo.x >= both_hi.x || both_lo.y >= both_hi.y) continue;
          // Each pair once: in the cell holding the lower corner of the boxes' intersection.
          if (cell(both_lo.x, lo.x, extent.x) != x || cell(both_lo.y, lo.y, extent.y) != y)
            continue;
          if (!interiors_overlap(a, b)) continue;
          auto key = std::make_tuple(a.mesh, a.triangle, b.mesh, b.triangle);
          if (key > std::make_tuple(b.mesh, b.triangle, a.mesh, a.triangle))
            key = std::make_tuple(b.mesh, b.triangle, a.mesh, a.triangle);
          if (!first || key < *first) first = key;
        }
    }
  if (!first) return std::nullopt;
  Uv1Overlap o;
  std::tie(o.mesh_a, o.triangle_a, o.mesh_b, o.triangle_b) = *first;
  return o;
}

}  // namespace

std::optional<Uv1Overlap> find_uv1_overlap(const Scene& scene) {
  std::vector<UvTriangle> tris;
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (!scene.meshes[m].uv1.empty()) collect_triangles(scene.meshes[m], int(m), tris);
  return first_overlap(tris);
}

std::optional<std::string> mesh_uv1_problem(const Mesh& mesh, const mat4& transform) {
  if (mesh.uv1.empty()) return "it has no uv1";
  if (mesh.uv1.size() != mesh.positions.size())
    return fmt::format("{} uv1 for {} vertices", mesh.uv1.size(), mesh.positions.size());
  for (size_t v = 0; v < mesh.uv1.size(); ++v) {
    const vec2 uv = mesh.uv1[v];
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
      return fmt::format("vertex {} has a non-finite uv1", v);
    // Light-map UVs address one texture once: coordinates past [0,1] are a tiling texture
    // layout, not a light-map's.
    if (uv.x < 0.0f || uv.x > 1.0f || uv.y < 0.0f || uv.y > 1.0f)
      return fmt::format("vertex {} has uv1 ({}, {}) outside [0,1]", v, uv.x, uv.y);
  }
  for (uint32_t i : mesh.indices)
    if (i >= mesh.positions.size())
      return fmt::format("index {} of {} vertices", i, mesh.positions.size());
  if (mesh.indices.size() % 3 != 0) return fmt::format("{} indices", mesh.indices.size());
  // A triangle with surface but no uv1 area would get no texel at all.
  const glm::dmat4 m(transform);
  Bounds3 bounds;
  for (const vec3& p : mesh.positions) bounds.extend(vec3(m * glm::dvec4(glm::dvec3(p), 1.0)));
  const double scale_sq = double(bounds.diagonal()) * bounds.diagonal();
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    glm::dvec2 c[3];
    vec3 w[3];
    uint32_t idx[3];
    for (int k = 0; k < 3; ++k) {
      idx[k] = mesh.indices[3 * t + size_t(k)];
      c[k] = glm::dvec2(mesh.uv1[idx[k]]);
      w[k] = vec3(m * glm::dvec4(glm::dvec3(mesh.positions[idx[k]]), 1.0));
    }
    if (covers_nothing(c) &&
        !is_degenerate_triangle(w[0], w[1], w[2], idx[0], idx[1], idx[2], scale_sq))
      return fmt::format("triangle {} has surface but no uv1 area", t);
  }
  std::vector<UvTriangle> tris;
  collect_triangles(mesh, 0, tris);
  if (const std::optional<Uv1Overlap> o = first_overlap(tris))
    return fmt::format("its triangles {} and {} overlap in uv1", o->triangle_a, o->triangle_b);
  return std::nullopt;
}

void check_given_uv1(const Scene& scene) {
  const std::optional<Uv1Overlap> o = find_uv1_overlap(scene);
  if (!o) return;
  throw Error(fmt::format(
      "uv1 of mesh '{}' triangle {} overlaps mesh '{}' triangle {}: overlapping light-map UVs "
      "would share texels (chart the scene anew instead of reusing its uv1)",
      scene.meshes[size_t(o->mesh_a)].name, o->triangle_a, scene.meshes[size_t(o->mesh_b)].name,
      o->triangle_b));
}

}  // namespace illum::atlas
