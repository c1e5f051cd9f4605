#include "illum/atlas/uv1_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "illum/core/error.h"

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

}  // namespace

std::optional<Uv1Overlap> find_uv1_overlap(const Scene& scene) {
  std::vector<UvTriangle> tris;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.uv1.empty()) continue;
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
      const double area2 = cross2(u.c[1] - u.c[0], u.c[2] - u.c[0]);
      const double longest = std::max({glm::length(u.c[1] - u.c[0]), glm::length(u.c[2] - u.c[1]),
                                       glm::length(u.c[0] - u.c[2])});
      if (std::abs(area2) <= kTouchTolerance * longest) continue;  // covers nothing
      if (area2 < 0.0) std::swap(u.c[1], u.c[2]);
      u.lo = glm::min(u.c[0], glm::min(u.c[1], u.c[2]));
      u.hi = glm::max(u.c[0], glm::max(u.c[1], u.c[2]));
      u.mesh = int(m);
      u.triangle = int(t);
      tris.push_back(u);
    }
  }
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
