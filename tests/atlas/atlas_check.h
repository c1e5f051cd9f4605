// An independent checker of every promise atlas.h makes about a built atlas, shared by the
// atlas tests, plus small scene builders. It re-derives coverage and overlaps from uv1 alone
// (no code from atlas.cpp), in double precision.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "illum/atlas/atlas.h"
#include "illum/core/image.h"
#include "illum/scene/mesh_processing.h"
#include "illum/scene/scene.h"

namespace illum::atlas::test {

using glm::dvec2;
using glm::dvec3;

inline double cross2(const dvec2& a, const dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// Calls f(x, y) for every texel of a W×H grid that the triangle p (texel units) touches,
// grazing included (closed sets): separating axes between the triangle and the texel square.
// Works for either winding and for zero-area triangles (segments, points).
template <typename F>
void for_each_touched_texel(const dvec2 p[3], int width, int height, F&& f) {
  const dvec2 lo = glm::min(p[0], glm::min(p[1], p[2]));
  const dvec2 hi = glm::max(p[0], glm::max(p[1], p[2]));
  const int x0 = std::max(0, int(std::floor(lo.x))),
            x1 = std::min(width - 1, int(std::floor(hi.x)));
  const int y0 = std::max(0, int(std::floor(lo.y))),
            y1 = std::min(height - 1, int(std::floor(hi.y)));
  const double area = cross2(p[1] - p[0], p[2] - p[0]);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const dvec2 corners[4] = {{x, y}, {x + 1, y}, {x, y + 1}, {x + 1, y + 1}};
      bool separated = false;
      for (int k = 0; k < 3 && !separated; ++k) {
        const dvec2 e = p[(k + 1) % 3] - p[k];
        if (e == dvec2(0.0)) continue;
        int above = 0, below = 0;
        for (const dvec2& c : corners) {
          const double s = cross2(e, c - p[k]);
          above += s > 0.0;
          below += s < 0.0;
        }
        // Inside lies on the side of the third vertex; for a segment, either side.
        if (area > 0.0)
          separated = below == 4;
        else if (area < 0.0)
          separated = above == 4;
        else
          separated = above == 4 || below == 4;
      }
      if (!separated) f(x, y);
    }
}

// Interior overlap of two triangles (either winding, non-zero area) deeper than `tolerance`.
inline bool interiors_overlap(const dvec2 a[3], const dvec2 b[3], double tolerance) {
  for (int side = 0; side < 2; ++side) {
    const dvec2* t = side == 0 ? a : b;
    const dvec2* o = side == 0 ? b : a;
    const double sign = cross2(t[1] - t[0], t[2] - t[0]) > 0.0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; ++k) {
      const dvec2 e = t[(k + 1) % 3] - t[k];
      double deepest = -1e300;  // how far inside this edge the other triangle reaches
      for (int j = 0; j < 3; ++j) deepest = std::max(deepest, sign * cross2(e, o[j] - t[k]));
      if (deepest <= tolerance * glm::length(e)) return false;
    }
  }
  return true;
}

struct AtlasReport {
  size_t covered_texels = 0;
  double occupancy = 0.0;          // covered texels / (width · height)
  double min_density_ratio = 0.0;  // world area / (uv area · W · H · s²) over triangles
  double max_density_ratio = 0.0;
  size_t triangles = 0;
  size_t degenerate = 0;
  size_t slivers = 0;          // non-degenerate triangles whose uv1 area is below float rounding
  std::vector<int32_t> owner;  // chart per texel (−1: none), for pictures
};

// The instance of each mesh (−1: none).
inline std::vector<int> instance_of_meshes(const Scene& scene) {
  std::vector<int> of(scene.meshes.size(), -1);
  for (size_t i = 0; i < scene.instances.size(); ++i) of[scene.instances[i].mesh] = int(i);
  return of;
}

// Checks `atlas` against `scene` (the scene it was built from, meshes unique) and `options`:
//  - layout: one per mesh, triangle corners map to the mesh's own vertices, counts consistent;
//  - uv1 inside [0,1]; every texel a triangle touches (conservatively) lies in its chart's
//    rectangle; no texel is touched by two charts; touched texels of different charts have
//    ≥ padding empty texels between them, and ≥ padding to the border; rectangles lie ≥
//    padding inside the border and are ≥ padding apart or nested;
//  - no two triangles overlap in uv1 (same chart or not) by more than 1e-3 + 4δ texels,
//    δ = 2⁻²⁴·W the uv1 rounding (float spacing near 1 is 2⁻²⁴; 1.2e-4 texel at W = 2048):
//    rounding of both triangles' vertices can make exactly shared seams disagree by ~2δ;
//  - texel density: each chart is scaled to the nominal density, so the uv1 areas of its
//    triangles (texels²) add up to their world areas / s², up to the uv1 rounding: a vertex
//    moved by δ = 2⁻²⁴·W texels changes a triangle's area by at most δ·perimeter, so the
//    tolerance per triangle is 2δ·P texels² (+1e-6 relative for the float conversions of
//    world positions), summed over the chart; and a triangle at angle θ to its chart's
//    axis has uv1 area = world area / s² · cos θ · f², f² ∈ [1, 1/cos θmax] the chart's
//    scale, so it lies in world/s² × [cos θmax, 1/cos θmax] ± its tolerance. s is the
//    mesh's own texel size where its instance has one (Instance::lightmap_texel_size).
//    Meshes in `given_uv1` kept their own UV1: only the chart sum holds for them. Slivers
//    whose uv1 area is below that bound are not tested for overlaps (their orientation is
//    below what float uv1 can hold).
inline AtlasReport check_atlas(const Scene& scene, const Atlas& atlas, const AtlasOptions& options,
                               const std::vector<int>& given_uv1 = {}) {
  AtlasReport report;
  const int W = atlas.width, H = atlas.height;
  EXPECT_EQ(W, options.resolution);
  EXPECT_EQ(H, options.resolution);
  EXPECT_GT(atlas.texel_size, 0.0f);
  if (options.texel_size > 0.0f) {
    EXPECT_EQ(atlas.texel_size, options.texel_size);
  }
  EXPECT_EQ(atlas.chart_count, int(atlas.charts.size()));
  if (W != options.resolution || H != options.resolution ||
      atlas.chart_count != int(atlas.charts.size()))
    return report;
  EXPECT_EQ(atlas.meshes.size(), scene.meshes.size());
  if (atlas.meshes.size() != scene.meshes.size()) return report;
  const int pad = options.padding;
  // Per chart: Σ uv1 area, Σ world area / s², Σ rounding tolerance (texels²).
  std::vector<double> chart_uv(atlas.charts.size(), 0.0), chart_world(atlas.charts.size(), 0.0),
      chart_rounding(atlas.charts.size(), 0.0);
  const double delta = std::ldexp(1.0, -24) * std::max(W, H);  // uv1 rounding, texels
  const double cos_max = std::cos(double(options.max_chart_angle) * M_PI / 180.0);
  const std::vector<int> instance_of = instance_of_meshes(scene);
  int reported = 0;
  auto fail = [&](const std::string& message) {
    if (++reported <= 10) ADD_FAILURE() << message;
  };

  // Chart rectangles: inside the atlas with `pad` to the border; any two are ≥ pad apart or
  // nested (a small chart in the empty space of a larger one's rectangle).
  std::vector<size_t> by_x(atlas.charts.size());
  for (size_t c = 0; c < by_x.size(); ++c) by_x[c] = c;
  std::sort(by_x.begin(), by_x.end(),
            [&](size_t a, size_t b) { return atlas.charts[a].x < atlas.charts[b].x; });
  auto contains = [](const AtlasChart& a, const AtlasChart& b) {
    return b.x >= a.x && b.y >= a.y && b.x + b.width <= a.x + a.width &&
           b.y + b.height <= a.y + a.height;
  };
  for (size_t i = 0; i < by_x.size(); ++i) {
    const AtlasChart& a = atlas.charts[by_x[i]];
    if (a.x < pad || a.y < pad || a.x + a.width > W - pad || a.y + a.height > H - pad ||
        a.width < 1 || a.height < 1)
      fail(fmt::format("chart {} rectangle ({}, {}) {}×{} is not ≥ {} texels inside the atlas",
                       by_x[i], a.x, a.y, a.width, a.height, pad));
    for (size_t j = i + 1; j < by_x.size() && atlas.charts[by_x[j]].x < a.x + a.width + pad; ++j) {
      const AtlasChart& b = atlas.charts[by_x[j]];
      const bool near = b.y < a.y + a.height + pad && a.y < b.y + b.height + pad;
      if (near && !contains(a, b) && !contains(b, a))
        fail(fmt::format("chart rectangles {} and {} are closer than {} texels and not nested",
                         by_x[i], by_x[j], pad));
    }
  }

  // Per triangle: uv1 in texels, coverage, density.
  struct Tri {
    dvec2 p[3];
    uint32_t chart;
    uint32_t touched_begin = 0, touched_end = 0;  // its texels in `touched`
  };
  std::vector<uint32_t> touched;  // texel indices, per triangle
  std::vector<Tri> tris;
  report.owner.assign(size_t(W) * H, -1);
  report.min_density_ratio = 1e300;
  report.max_density_ratio = -1e300;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const MeshLayout& layout = atlas.meshes[m];
    EXPECT_EQ(layout.source_vertex_count, mesh.positions.size()) << mesh.name;
    EXPECT_EQ(layout.uv1.size(), layout.source_vertex.size()) << mesh.name;
    EXPECT_EQ(layout.indices.size(), mesh.indices.size()) << mesh.name;
    EXPECT_EQ(layout.triangle_chart.size(), mesh.triangle_count()) << mesh.name;
    if (layout.source_vertex_count != mesh.positions.size() ||
        layout.uv1.size() != layout.source_vertex.size() ||
        layout.indices.size() != mesh.indices.size() ||
        layout.triangle_chart.size() != mesh.triangle_count())
      return report;
    const glm::dmat4 transform(instance_of[m] >= 0 ? scene.instances[instance_of[m]].transform
                                                   : mat4(1.0f));
    const double s = instance_of[m] >= 0 && scene.instances[instance_of[m]].lightmap_texel_size > 0
                         ? double(scene.instances[instance_of[m]].lightmap_texel_size)
                         : double(atlas.texel_size);
    const bool own_uv1 = std::find(given_uv1.begin(), given_uv1.end(), int(m)) != given_uv1.end();
    Bounds3 bounds;
    std::vector<dvec3> world(mesh.positions.size());
    for (size_t v = 0; v < world.size(); ++v) {
      world[v] = dvec3(transform * glm::dvec4(dvec3(mesh.positions[v]), 1.0));
      bounds.extend(vec3(world[v]));
    }
    const double scale_sq = double(bounds.diagonal()) * bounds.diagonal();
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      Tri tri;
      tri.chart = layout.triangle_chart[t];
      uint32_t src[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = layout.indices[3 * t + k];
        if (v >= layout.source_vertex.size()) {
          fail(fmt::format("mesh {} triangle {} uses vertex {} of {}", m, t, v,
                           layout.source_vertex.size()));
          return report;
        }
        src[k] = layout.source_vertex[v];
        if (src[k] != mesh.indices[3 * t + k])
          fail(fmt::format("mesh {} triangle {} corner {} comes from vertex {}, not {}", m, t, k,
                           src[k], mesh.indices[3 * t + k]));
        const vec2 uv = layout.uv1[v];
        if (!(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f))
          fail(fmt::format("mesh {} triangle {} has uv1 ({}, {}) outside [0,1]", m, t, uv.x, uv.y));
        tri.p[k] = dvec2(uv) * dvec2(W, H);
      }
      if (instance_of[m] < 0) {
        EXPECT_EQ(tri.chart, kNoChart);
        continue;
      }
      ++report.triangles;
      if (tri.chart >= atlas.charts.size()) {
        fail(fmt::format("mesh {} triangle {} is in chart {} of {}", m, t, tri.chart,
                         atlas.charts.size()));
        continue;
      }
      const AtlasChart& r = atlas.charts[tri.chart];
      if (r.mesh != int(m)) fail(fmt::format("chart {} is not of mesh {}", tri.chart, m));
      tri.touched_begin = uint32_t(touched.size());
      for_each_touched_texel(tri.p, W, H, [&](int x, int y) {
        touched.push_back(uint32_t(y * W + x));
        if (x < r.x || x >= r.x + r.width || y < r.y || y >= r.y + r.height)
          fail(fmt::format("mesh {} triangle {} touches texel ({}, {}) outside its chart {}", m, t,
                           x, y, tri.chart));
        int32_t& o = report.owner[size_t(y) * W + x];
        if (o >= 0 && o != int32_t(tri.chart))
          fail(fmt::format("texel ({}, {}) is touched by charts {} and {}", x, y, o, tri.chart));
        o = int32_t(tri.chart);
      });
      tri.touched_end = uint32_t(touched.size());
      const dvec3 a = world[src[0]], b = world[src[1]], c = world[src[2]];
      if (is_degenerate_triangle(vec3(a), vec3(b), vec3(c), src[0], src[1], src[2], scale_sq)) {
        ++report.degenerate;
        continue;
      }
      // In texels²: world_area·cos θmax ≤ uv_area ≤ world_area, ± the rounding bound (in
      // this form, without a division, it also holds for slivers of almost no area).
      const double world_area = 0.5 * glm::length(glm::cross(b - a, c - a)) / (s * s);
      const double uv_area = 0.5 * cross2(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
      const double perimeter = glm::length(tri.p[1] - tri.p[0]) + glm::length(tri.p[2] - tri.p[1]) +
                               glm::length(tri.p[0] - tri.p[2]);
      const double rounding = 2.0 * delta * perimeter + 1e-6 * world_area;
      chart_uv[tri.chart] += std::abs(uv_area);
      chart_world[tri.chart] += world_area;
      chart_rounding[tri.chart] += rounding;
      if (!own_uv1 &&
          (uv_area < world_area * cos_max - rounding || uv_area > world_area / cos_max + rounding))
        fail(fmt::format(
            "mesh {} triangle {}: uv1 area {} texels² is outside [{}, {}] (world "
            "area × [cos θmax, 1/cos θmax]) ± {}; world ({}, {}, {}) ({}, {}, {}) ({}, {}, "
            "{}), uv1·size ({}, {}) ({}, {}) ({}, {})",
            m, t, uv_area, world_area * cos_max, world_area / cos_max, rounding, a.x, a.y, a.z, b.x,
            b.y, b.z, c.x, c.y, c.z, tri.p[0].x, tri.p[0].y, tri.p[1].x, tri.p[1].y, tri.p[2].x,
            tri.p[2].y));
      // The printed range: triangles large enough for rounding not to matter.
      if (uv_area > 1e4 * rounding) {
        const double ratio = world_area / uv_area;
        report.min_density_ratio = std::min(report.min_density_ratio, ratio);
        report.max_density_ratio = std::max(report.max_density_ratio, ratio);
      }
      if (uv_area <= rounding) {  // a sliver: its orientation is below what uv1 can hold
        ++report.slivers;
        continue;
      }
      tris.push_back(tri);
    }
  }

  // Every chart at the nominal density: its uv1 area is its world area / s².
  for (size_t c = 0; c < atlas.charts.size(); ++c)
    if (std::abs(chart_uv[c] - chart_world[c]) > chart_rounding[c])
      fail(
          fmt::format("chart {} (mesh {}): uv1 area {} texels² for a world area of {} texels² "
                      "(density {:.6f} of the nominal, tolerance ±{})",
                      c, atlas.charts[c].mesh, chart_uv[c], chart_world[c],
                      chart_uv[c] / chart_world[c], chart_rounding[c]));

  // Touched texels of different charts are ≥ pad apart (Chebyshev distance > pad).
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int32_t o = report.owner[size_t(y) * W + x];
      if (o < 0) continue;
      ++report.covered_texels;
      if (x < pad || y < pad || x >= W - pad || y >= H - pad)
        fail(fmt::format("texel ({}, {}) of chart {} is within {} of the border", x, y, o, pad));
      for (int dy = -pad; dy <= pad; ++dy)
        for (int dx = -pad; dx <= pad; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
          const int32_t other = report.owner[size_t(ny) * W + nx];
          if (other >= 0 && other != o)
            fail(
                fmt::format("texels ({}, {}) of chart {} and ({}, {}) of chart {} are closer than "
                            "{} texels",
                            x, y, o, nx, ny, other, pad));
        }
    }
  report.occupancy = double(report.covered_texels) / (double(W) * H);

  // No two triangles overlap: bucket them by the texels they touch; test each pair once, in
  // the texel holding the lower corner of their boxes' intersection.
  std::vector<uint32_t> begin(size_t(W) * H + 1, 0);
  auto visit = [&](auto&& f) {
    for (uint32_t i = 0; i < tris.size(); ++i)
      for (uint32_t k = tris[i].touched_begin; k < tris[i].touched_end; ++k) f(i, touched[k]);
  };
  visit([&](uint32_t, size_t texel) { ++begin[texel + 1]; });
  for (size_t i = 1; i < begin.size(); ++i) begin[i] += begin[i - 1];
  std::vector<uint32_t> fill(begin.begin(), begin.end() - 1), items(begin.back());
  visit([&](uint32_t i, size_t texel) { items[fill[texel]++] = i; });
  size_t overlaps = 0;
  const double overlap_tolerance = 1e-3 + 4.0 * delta;
  for (size_t texel = 0; texel + 1 < begin.size(); ++texel)
    for (uint32_t p = begin[texel]; p < begin[texel + 1]; ++p)
      for (uint32_t q = p + 1; q < begin[texel + 1]; ++q) {
        const Tri &a = tris[items[p]], &b = tris[items[q]];
        const dvec2 lo = glm::max(glm::min(a.p[0], glm::min(a.p[1], a.p[2])),
                                  glm::min(b.p[0], glm::min(b.p[1], b.p[2])));
        const size_t first = size_t(std::clamp(int(std::floor(lo.y)), 0, H - 1)) * W +
                             size_t(std::clamp(int(std::floor(lo.x)), 0, W - 1));
        if (first != texel) continue;
        if (interiors_overlap(a.p, b.p, overlap_tolerance)) {
          ++overlaps;
          fail(fmt::format(
              "triangles of charts {} and {} overlap in uv1 near texel ({}, {}): "
              "({}, {}) ({}, {}) ({}, {}) and ({}, {}) ({}, {}) ({}, {})",
              a.chart, b.chart, texel % W, texel / W, a.p[0].x, a.p[0].y, a.p[1].x, a.p[1].y,
              a.p[2].x, a.p[2].y, b.p[0].x, b.p[0].y, b.p[1].x, b.p[1].y, b.p[2].x, b.p[2].y));
        }
      }
  EXPECT_EQ(overlaps, 0u);
  if (reported > 10) ADD_FAILURE() << reported << " problems in all";
  return report;
}

// A picture of the atlas for people: each chart's touched texels in a colour of its own,
// its rectangle's unused cells dark grey, padding black.
inline Image atlas_picture(const Atlas& atlas, const AtlasReport& report) {
  Image image(atlas.width, atlas.height, 3, 0.0f);
  for (const AtlasChart& r : atlas.charts)
    for (int y = r.y; y < r.y + r.height; ++y)
      for (int x = r.x; x < r.x + r.width; ++x) image.set_rgb(x, y, Color(0.08f));
  for (int y = 0; y < atlas.height; ++y)
    for (int x = 0; x < atlas.width; ++x) {
      const int32_t c = report.owner[size_t(y) * atlas.width + x];
      if (c < 0) continue;
      uint32_t h = uint32_t(c) * 2654435761u;
      h ^= h >> 15;
      h *= 2246822519u;
      h ^= h >> 13;
      image.set_rgb(x, y,
                    Color(0.25f + 0.75f * float(h & 255) / 255.0f,
                          0.25f + 0.75f * float((h >> 8) & 255) / 255.0f,
                          0.25f + 0.75f * float((h >> 16) & 255) / 255.0f));
    }
  return image;
}

// Writes the picture to $ILLUM_ATLAS_PNG_DIR/NAME.png when that variable is set.
inline void maybe_write_picture(const std::string& name, const Atlas& atlas,
                                const AtlasReport& report) {
  const char* folder = std::getenv("ILLUM_ATLAS_PNG_DIR");
  if (!folder) return;
  ImageWriteOptions options;
  options.srgb = false;
  write_image(fmt::format("{}/{}.png", folder, name), atlas_picture(atlas, report), options);
}

// Scene builders.
inline Mesh make_mesh(const std::string& name, std::vector<vec3> positions,
                      std::vector<uint32_t> indices) {
  Mesh mesh;
  mesh.name = name;
  mesh.positions = std::move(positions);
  mesh.indices = std::move(indices);
  return mesh;
}

inline Scene make_scene(std::vector<Mesh> meshes, std::vector<mat4> transforms = {}) {
  Scene scene;
  scene.name = "test";
  scene.materials.resize(1);
  for (size_t m = 0; m < meshes.size(); ++m) {
    Instance instance;
    instance.name = fmt::format("instance{}", m);
    instance.mesh = int(m);
    if (m < transforms.size()) instance.transform = transforms[m];
    scene.instances.push_back(instance);
  }
  scene.meshes = std::move(meshes);
  return scene;
}

// An n×n grid of unit quads in the xz-plane (normal +y), each quad with its own four
// vertices (as OBJ/glTF loaders produce at uv seams).
inline Mesh split_grid(int n, float size = 1.0f) {
  Mesh mesh;
  mesh.name = "grid";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t base = uint32_t(mesh.positions.size());
      for (int k = 0; k < 4; ++k)
        mesh.positions.push_back(vec3(float(i + (k & 1)) * size, 0.0f, float(j + (k >> 1)) * size));
      // Counter-clockwise seen from +y: (0,0,0) → (0,0,1) → (1,0,0).
      for (uint32_t v : {0u, 2u, 1u, 1u, 2u, 3u}) mesh.indices.push_back(base + v);
    }
  return mesh;
}

}  // namespace illum::atlas::test
