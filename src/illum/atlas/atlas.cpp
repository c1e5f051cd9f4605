// Light-map atlas: options, the charts of every mesh (charting.cpp), the texel size and the
// packing (packing.cpp), the per-mesh layouts with seam vertices split, and apply_atlas.
// The choices and their reasons are in README.md.
#include "illum/atlas/atlas.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "illum/atlas/charts.h"
#include "illum/atlas/uv1_check.h"
#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/mesh_processing.h"

namespace illum::atlas {

using glm::dvec2;
using glm::dvec3;
using namespace detail;  // Chart, chart_mesh, pack_charts, finest_texel_size, ...

AtlasOptions AtlasOptions::from_params(const Params& params) {
  AtlasOptions o;
  o.resolution = params.get_int_in("resolution", o.resolution, kMinResolution, kMaxResolution);
  o.texel_size = params.get<float>("texel_size", o.texel_size);
  if (o.texel_size < 0.0f)
    throw Error(fmt::format("{} = {} must be ≥ 0 (metres per texel; 0 = the finest that fits)",
                            params.where("texel_size"), o.texel_size));
  o.padding = params.get_int_in("padding", o.padding, 1, 16);
  o.reuse_uv1 = params.get<bool>("reuse_uv1", o.reuse_uv1);
  o.max_chart_angle = params.get<float>("max_chart_angle", o.max_chart_angle);
  if (!(o.max_chart_angle > 0.0f && o.max_chart_angle <= 89.0f))
    throw Error(fmt::format("{} = {} is outside (0, 89] degrees", params.where("max_chart_angle"),
                            o.max_chart_angle));
  return o;
}

namespace {

// Sparse charts are cut when the space they waste exceeds this fraction of the scene's
// surface area (charting.cpp).
constexpr double kMaxChartWaste = 1e-4;

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
  // A mesh's own UV1, when valid, is its chart; an invalid one is a warning and the mesh is
  // charted anew (README.md "Given UV1" says why this is no error).
  std::vector<std::string> uv1_problem(scene.meshes.size());
  std::vector<uint8_t> reused(scene.meshes.size(), 0);
  tbb::parallel_for(size_t(0), scene.meshes.size(), [&](size_t m) {
    if (instance_of[m] < 0) return;
    const Mesh& mesh = scene.meshes[m];
    const mat4& transform = scene.instances[instance_of[m]].transform;
    try {
      if (options.reuse_uv1 && !mesh.uv1.empty()) {
        if (const std::optional<std::string> problem = mesh_uv1_problem(mesh, transform)) {
          uv1_problem[m] = *problem;
        } else {
          per_mesh[m].push_back(chart_from_uv1(mesh, m, transform));
          reused[m] = 1;
          return;
        }
      }
      per_mesh[m] = chart_mesh(mesh, m, transform, cos_max, waste_limit);
    } catch (...) {
      failure[m] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : failure)
    if (e) std::rethrow_exception(e);
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (!uv1_problem[m].empty())
      log::warn("atlas: the UV1 of {} cannot be its light-map layout ({}): charted anew",
                mesh_label(scene.meshes[m], m), uv1_problem[m]);
  std::vector<Chart> charts;
  bool any_free = false;  // a chart at the atlas's texel size
  float smallest_own = 0.0f;
  for (size_t m = 0; m < per_mesh.size(); ++m) {
    const float own =
        instance_of[m] >= 0 ? scene.instances[instance_of[m]].lightmap_texel_size : 0.0f;
    if (!per_mesh[m].empty() && own > 0.0f)
      smallest_own = smallest_own > 0.0f ? std::min(smallest_own, own) : own;
    for (Chart& c : per_mesh[m]) {
      c.texel_size = own;
      any_free = any_free || !(own > 0.0f);
      charts.push_back(std::move(c));
    }
  }

  const int resolution = options.resolution;
  double s = options.texel_size;
  // Every chart at its mesh's own texel size: nothing to search; the atlas reports the
  // given size, else the finest of the meshes'.
  if (!any_free && !(s > 0.0)) s = smallest_own;
  std::vector<ivec2> origins;
  if (!charts.empty()) {
    if (s > 0.0 && !any_free) {
      if (!pack_charts(charts, s, resolution, options.padding, &origins))
        throw Error(fmt::format(
            "atlas: {} charts do not fit a {}×{} atlas (padding {}) at the texel sizes their "
            "scene file gives them (\"lightmap\": {{\"texel_size\": ...}}, the finest {} m)",
            charts.size(), resolution, resolution, options.padding, smallest_own));
    } else if (s > 0.0) {
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
    const double cs = chart.texel(s);
    const ivec2 cells = cells_of(chart.size, cs);
    atlas.charts[c] = {chart.mesh, origins[c].x, origins[c].y, cells.x, cells.y};
    const dvec2 offset = dvec2(origins[c]) + offset_in_cells(chart, cells, cs);
    for (size_t i = 0; i < chart.triangles.size(); ++i) {
      const uint32_t t = chart.triangles[i];
      chart_of[chart.mesh][t] = uint32_t(c);
      for (int k = 0; k < 3; ++k)
        corner_uv[chart.mesh][3 * t + k] =
            vec2((offset + chart.corners[3 * i + k] / cs) * inv_resolution);
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
    layout.reused_uv1 = reused[m] != 0;
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

Atlas chart_scene(Scene& scene, const AtlasOptions& options) {
  make_meshes_unique(scene);
  Atlas atlas = build_atlas(scene, options);
  apply_atlas(scene, atlas);
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
