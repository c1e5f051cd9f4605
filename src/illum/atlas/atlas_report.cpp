#include "illum/atlas/atlas_report.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/scene/mesh_processing.h"

namespace illum::atlas {
namespace {

using glm::dvec2;
using glm::dvec3;

struct Accumulator {
  DensityStats stats;
  double stretch_sq_area = 0.0;  // Σ area · L2²

  void add(double area, double nominal, double sigma1, double sigma2, double uv_texels) {
    DensityStats& s = stats;
    const double density = sigma1 * sigma2;
    if (s.triangles == 0) {
      s.min_density = s.max_density = density;
    } else {
      s.min_density = std::min(s.min_density, density);
      s.max_density = std::max(s.max_density, density);
    }
    s.max_anisotropy = std::max(s.max_anisotropy, sigma2 > 0.0 ? sigma1 / sigma2 : kInf);
    s.world_area += area;
    s.nominal_texels += nominal;
    s.uv_texels += uv_texels;
    stretch_sq_area += area * 0.5 * (sigma1 * sigma1 + sigma2 * sigma2);
    ++s.triangles;
  }
  void merge(const Accumulator& o) {
    if (o.stats.triangles == 0) return;
    if (stats.triangles == 0) {
      stats.min_density = o.stats.min_density;
      stats.max_density = o.stats.max_density;
    }
    stats.min_density = std::min(stats.min_density, o.stats.min_density);
    stats.max_density = std::max(stats.max_density, o.stats.max_density);
    stats.max_anisotropy = std::max(stats.max_anisotropy, o.stats.max_anisotropy);
    stats.world_area += o.stats.world_area;
    stats.nominal_texels += o.stats.nominal_texels;
    stats.uv_texels += o.stats.uv_texels;
    stretch_sq_area += o.stretch_sq_area;
    stats.triangles += o.stats.triangles;
  }
  DensityStats finish() const {
    DensityStats s = stats;
    s.mean_density = s.nominal_texels > 0.0 ? s.uv_texels / s.nominal_texels : 0.0;
    s.rms_l2_stretch = s.world_area > 0.0 ? std::sqrt(stretch_sq_area / s.world_area) : 0.0;
    return s;
  }
};

}  // namespace

AtlasStats measure_atlas(const Scene& scene, const Atlas& atlas) {
  AtlasStats out;
  out.charts = atlas.chart_count;
  for (const AtlasChart& c : atlas.charts) out.chart_texels += double(c.width) * c.height;
  std::vector<int> instance_of(scene.meshes.size(), -1);
  for (size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].mesh >= 0 && size_t(scene.instances[i].mesh) < scene.meshes.size())
      instance_of[size_t(scene.instances[i].mesh)] = int(i);
  const dvec2 size(atlas.width, atlas.height);
  Accumulator all;
  double uv_texels = 0.0;
  out.meshes.resize(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (instance_of[m] < 0) continue;
    if (mesh.uv1.size() != mesh.positions.size() || mesh.indices.size() % 3 != 0)
      throw Error(fmt::format("measure_atlas: mesh '{}' (#{}) has {} uv1 for {} vertices",
                              mesh.name, m, mesh.uv1.size(), mesh.positions.size()));
    const Instance& instance = scene.instances[size_t(instance_of[m])];
    const double s =
        instance.lightmap_texel_size > 0.0f ? instance.lightmap_texel_size : atlas.texel_size;
    const glm::dmat4 transform(instance.transform);
    Bounds3 bounds;
    for (const vec3& p : mesh.positions) bounds.extend(vec3(transform * glm::dvec4(dvec3(p), 1.0)));
    const double scale_sq = double(bounds.diagonal()) * bounds.diagonal();
    Accumulator acc;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      dvec3 w[3];
      dvec2 u[3];
      uint32_t src[3];
      for (int k = 0; k < 3; ++k) {
        src[k] = mesh.indices[3 * t + size_t(k)];
        if (src[k] >= mesh.positions.size())
          throw Error(fmt::format("measure_atlas: mesh '{}' (#{}) uses vertex {} of {}", mesh.name,
                                  m, src[k], mesh.positions.size()));
        w[k] = dvec3(transform * glm::dvec4(dvec3(mesh.positions[src[k]]), 1.0));
        u[k] = dvec2(mesh.uv1[src[k]]) * size;
      }
      if (is_degenerate_triangle(vec3(w[0]), vec3(w[1]), vec3(w[2]), src[0], src[1], src[2],
                                 scale_sq))
        continue;
      // World triangle in an orthonormal frame of its plane, in texels of the nominal size.
      const dvec3 e1 = w[1] - w[0], e2 = w[2] - w[0];
      const double l1 = glm::length(e1);
      const dvec3 x = e1 / l1;
      const dvec3 n = glm::cross(e1, e2);
      const double twice_area = glm::length(n);
      if (!(twice_area > 0.0)) continue;
      const dvec3 y = glm::cross(n / twice_area, x);
      const dvec2 p1(l1 / s, 0.0), p2(glm::dot(e2, x) / s, glm::dot(e2, y) / s);
      const dvec2 q1 = u[1] - u[0], q2 = u[2] - u[0];
      const double det_p = p1.x * p2.y - p1.y * p2.x;
      const double uv_area = 0.5 * std::abs(q1.x * q2.y - q1.y * q2.x);
      if (!(uv_area > 0.0)) continue;
      // uv = A p: A = [q1 q2] [p1 p2]⁻¹; σ² are the eigenvalues of AᵀA.
      const double a = (q1.x * p2.y - q2.x * p1.y) / det_p, b = (q2.x * p1.x - q1.x * p2.x) / det_p;
      const double c = (q1.y * p2.y - q2.y * p1.y) / det_p, d = (q2.y * p1.x - q1.y * p2.x) / det_p;
      const double trace = a * a + b * b + c * c + d * d;
      const double det = std::abs(a * d - b * c);
      const double root = std::sqrt(std::max(0.0, 0.25 * trace * trace - det * det));
      const double sigma1 = std::sqrt(0.5 * trace + root);
      const double sigma2 = sigma1 > 0.0 ? det / sigma1 : 0.0;
      const double area = 0.5 * twice_area;
      acc.add(area, area / (s * s), sigma1, sigma2, uv_area);
      uv_texels += uv_area;
    }
    out.meshes[m] = acc.finish();
    all.merge(acc);
  }
  out.all = all.finish();
  out.utilisation = uv_texels / (size.x * size.y);
  return out;
}

}  // namespace illum::atlas
