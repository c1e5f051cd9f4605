#include "illum/bake/lightmap_coplanar.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>

#include "illum/bake/lightmap_seams.h"
#include "illum/core/rng.h"

namespace illum::bake {
namespace {

struct EdgeLine {
  vec3 dir{0.0f};       // unit, p[0] → p[1]
  float length = 0.0f;  // world
  float texel = 0.0f;   // world size of one texel along the edge
};

EdgeLine line_of(const OpenEdge& e) {
  EdgeLine l;
  l.length = glm::length(e.p[1] - e.p[0]);
  const float texels = glm::length(e.uv[1] - e.uv[0]);
  if (!(l.length > 0.0f) || !(texels > 1e-6f)) return l;  // unusable: no direction or uv
  l.dir = (e.p[1] - e.p[0]) / l.length;
  l.texel = l.length / texels;
  return l;
}

struct CellHash {
  size_t operator()(const glm::i64vec3& k) const {
    return static_cast<size_t>(hash_mix(uint64_t(k.x), uint64_t(k.y), uint64_t(k.z)));
  }
};

// Tests one pair; on a match appends its samples (side 0: `a`) and returns true.
bool match_pair(const OpenEdge& a, const EdgeLine& la, const OpenEdge& b, const EdgeLine& lb,
                float tolerance, std::vector<SeamSample>& samples) {
  if (glm::dot(a.plane_normal, b.plane_normal) < kCoplanarCos) return false;  // plane or facing
  if (std::abs(glm::dot(la.dir, lb.dir)) < kCoplanarCos) return false;        // not parallel
  if (glm::dot(a.inward, b.inward) >= 0.0f) return false;  // same side: surfaces overlap
  const float gap = std::max(tolerance, kCoplanarGapTexels * std::max(la.texel, lb.texel));
  // b's end points along a's line; the overlap [lo, hi] in a's arc length.
  const float s0 = glm::dot(b.p[0] - a.p[0], la.dir), s1 = glm::dot(b.p[1] - a.p[0], la.dir);
  const float lo = std::max(0.0f, std::min(s0, s1)), hi = std::min(la.length, std::max(s0, s1));
  if (!(hi - lo > gap)) return false;  // touching at a corner, or apart
  // Where a point at arc length s of a lies on b (parameter in [0, 1]).
  const auto on_b = [&](float s) {
    const vec3 q = a.p[0] + s * la.dir;
    return std::clamp(glm::dot(q - b.p[0], lb.dir) / lb.length, 0.0f, 1.0f);
  };
  bool split = false;
  for (const float s : {lo, hi}) {
    const float ua = s / la.length, ub = on_b(s);
    if (glm::length(glm::mix(a.p[0], a.p[1], ua) - glm::mix(b.p[0], b.p[1], ub)) > gap)
      return false;  // parallel lines, but not close along the overlap
    const vec3 na = glm::normalize(glm::mix(a.normal[0], a.normal[1], ua));
    const vec3 nb = glm::normalize(glm::mix(b.normal[0], b.normal[1], ub));
    if (!(glm::dot(na, nb) >= kSeamNormalCos)) return false;  // shading differs: no seam
    split = split ||
            glm::length(glm::mix(a.uv[0], a.uv[1], ua) - glm::mix(b.uv[0], b.uv[1], ub)) > 1e-3f;
  }
  if (!split) return false;  // one chart continuing across the junction: nothing to join
  // Texels of overlap on the finer side; a whole number within float rounding (15.000001)
  // gets that many texels' samples, not one more.
  const float texels = (hi - lo) / std::min(la.texel, lb.texel);
  const int n = std::max(2, int(std::ceil(texels * float(kSeamSamplesPerTexel) - 1e-3f)));
  for (int k = 0; k < n; ++k) {
    const float s = lo + (hi - lo) * (float(k) + 0.5f) / float(n);
    samples.push_back(
        {{glm::mix(a.uv[0], a.uv[1], s / la.length), glm::mix(b.uv[0], b.uv[1], on_b(s))}});
  }
  return true;
}

}  // namespace

int64_t find_coplanar_seams(const std::vector<OpenEdge>& edges, float tolerance,
                            std::vector<SeamSample>& samples) {
  std::vector<EdgeLine> lines(edges.size());
  double total_length = 0.0;
  float widest_gap = tolerance;
  size_t usable = 0;
  for (size_t i = 0; i < edges.size(); ++i) {
    lines[i] = line_of(edges[i]);
    if (!(lines[i].texel > 0.0f)) continue;
    total_length += lines[i].length;
    widest_gap = std::max(widest_gap, kCoplanarGapTexels * lines[i].texel);
    ++usable;
  }
  if (usable < 2) return 0;
  // Cells about one edge long, at least twice the widest gap. Each edge is entered in the
  // cells of points a quarter cell apart along it; two edges that overlap within a gap have
  // such points within ¼ + ¼ + ½ of a cell of each other, so in the same or adjacent cells.
  const float cell = std::max(float(total_length / double(usable)), 2.0f * widest_gap);
  const auto cell_of = [cell](const vec3& p) {
    return glm::i64vec3(int64_t(std::floor(p.x / cell)), int64_t(std::floor(p.y / cell)),
                        int64_t(std::floor(p.z / cell)));
  };
  const auto cells_along = [&](size_t i) {
    const int steps = int(std::ceil(lines[i].length / (0.25f * cell)));
    std::vector<glm::i64vec3> cells;
    for (int k = 0; k <= steps; ++k)
      cells.push_back(cell_of(glm::mix(edges[i].p[0], edges[i].p[1], float(k) / float(steps))));
    std::sort(cells.begin(), cells.end(), [](const glm::i64vec3& x, const glm::i64vec3& y) {
      return std::tie(x.x, x.y, x.z) < std::tie(y.x, y.y, y.z);
    });
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    return cells;
  };
  std::unordered_map<glm::i64vec3, std::vector<int>, CellHash> grid;
  for (size_t i = 0; i < edges.size(); ++i)
    if (lines[i].texel > 0.0f)
      for (const glm::i64vec3& c : cells_along(i)) grid[c].push_back(int(i));

  int64_t pairs = 0;
  std::vector<int> candidates;
  for (size_t i = 0; i < edges.size(); ++i) {
    if (!(lines[i].texel > 0.0f)) continue;
    candidates.clear();
    for (const glm::i64vec3& c : cells_along(i))
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const auto it = grid.find(c + glm::i64vec3(dx, dy, dz));
            if (it == grid.end()) continue;
            for (const int j : it->second)
              if (j > int(i)) candidates.push_back(j);  // each pair once
          }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    for (const int j : candidates)
      if (match_pair(edges[i], lines[i], edges[size_t(j)], lines[size_t(j)], tolerance, samples))
        ++pairs;
  }
  return pairs;
}

}  // namespace illum::bake
