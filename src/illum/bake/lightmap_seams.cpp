#include "illum/bake/lightmap_seams.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "illum/core/error.h"
#include "illum/core/parallel.h"

namespace illum::bake {
namespace {

// How far past a back face a moved sample lands, in texel sizes: far above float rounding
// at any scene scale offset_ray_origin handles (1e-4 of the coordinates), far below a texel,
// so the sample still stands for its texel.
constexpr float kPastFace = 0.01f;
constexpr int kDirections = 8;

struct TriangleCorners {
  vec3 p[3];
  vec2 uv[3];  // in texels
};

TriangleCorners corners(const Scene& scene, const atlas::TexelRaster& raster,
                        const atlas::TexelSample& s) {
  const Instance& inst = scene.instances[static_cast<size_t>(s.instance)];
  const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
  TriangleCorners c;
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.indices[3 * static_cast<size_t>(s.triangle) + static_cast<size_t>(k)];
    c.p[k] = vec3(inst.transform * vec4(mesh.positions[v], 1.0f));
    c.uv[k] = mesh.uv1[v] * vec2(float(raster.width), float(raster.height));
  }
  return c;
}

// The closest back-face hit among the tangent-plane rays from `p` (lifted off the plane of
// normal `ng`), as a distance along `*direction`; infinity when every ray is free or hits
// a front face first.
float nearest_back_face(const RayTracer& tracer, const vec3& p, const vec3& ng, float reach,
                        vec3* direction) {
  const Frame frame = Frame::from_normal(ng);
  float nearest = kInf;
  for (int k = 0; k < kDirections; ++k) {
    const float angle = float(k) * (2.0f * kPi / kDirections);
    const vec3 dir = std::cos(angle) * frame.t + std::sin(angle) * frame.b;
    // Lifted as a ray leaving the surface is (offset_ray_origin along the normal), so the
    // sample's own triangle and a coplanar face it lies on are not hit.
    Ray ray{offset_ray_origin(p, ng, ng), dir, 0.0f, reach};
    Hit hit;
    if (!tracer.intersect(ray, &hit)) continue;
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    if (glm::dot(si.ng, dir) > 0.0f && hit.t < nearest) {
      nearest = hit.t;
      *direction = dir;
    }
  }
  return nearest;
}

}  // namespace

float texel_world_size(const Scene& scene, const atlas::TexelRaster& raster,
                       const atlas::TexelSample& s) {
  const TriangleCorners c = corners(scene, raster, s);
  // World edges E = J · uv edges; J = E · inverse(uv edges) (3×2), then the largest
  // singular value from the 2×2 JᵀJ.
  const glm::dvec2 d1(c.uv[1] - c.uv[0]), d2(c.uv[2] - c.uv[0]);
  const double det = d1.x * d2.y - d1.y * d2.x;
  if (!(std::abs(det) > 0.0)) return 0.0f;
  const glm::dvec3 e1(c.p[1] - c.p[0]), e2(c.p[2] - c.p[0]);
  const glm::dvec3 ju = (d2.y * e1 - d1.y * e2) / det;  // ∂p/∂u per texel
  const glm::dvec3 jv = (d1.x * e2 - d2.x * e1) / det;  // ∂p/∂v per texel
  const double a = glm::dot(ju, ju), b = glm::dot(ju, jv), d = glm::dot(jv, jv);
  const double lambda = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  return static_cast<float>(std::sqrt(lambda));
}

TexelPushOut keep_texels_out_of_geometry(const Scene& scene, const RayTracer& tracer,
                                         atlas::TexelRaster& raster) {
  if (raster.sample_of.size() != size_t(raster.width) * size_t(raster.height))
    throw Error(fmt::format("texel push-out: malformed texel raster ({}x{}, {} entries)",
                            raster.width, raster.height, raster.sample_of.size()));
  const int64_t count = static_cast<int64_t>(raster.samples.size());
  std::vector<uint8_t> reject(raster.samples.size(), 0);
  std::atomic<int64_t> moved{0};
  parallel_for(
      count,
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
          atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
          const float h = texel_world_size(scene, raster, s);
          if (!(h > 0.0f) || !std::isfinite(h)) continue;
          vec3 dir(0.0f);
          const float t = nearest_back_face(tracer, s.position, s.geometric_normal, h, &dir);
          if (!(t < kInf)) continue;
          const vec3 moved_to = s.position + (t + kPastFace * h) * dir;
          vec3 again(0.0f);
          if (nearest_back_face(tracer, moved_to, s.geometric_normal, h, &again) < kInf) {
            reject[static_cast<size_t>(i)] = 1;
            continue;
          }
          s.position = moved_to;
          moved.fetch_add(1, std::memory_order_relaxed);
        }
      },
      64);

  TexelPushOut out;
  out.moved = moved.load();
  size_t kept = 0;
  for (size_t i = 0; i < raster.samples.size(); ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    const size_t texel = size_t(s.y) * size_t(raster.width) + size_t(s.x);
    if (reject[i]) {
      raster.sample_of[texel] = -1;
      ++out.rejected;
      continue;
    }
    raster.samples[kept] = s;
    raster.sample_of[texel] = static_cast<int32_t>(kept);
    ++kept;
  }
  raster.samples.resize(kept);
  return out;
}

}  // namespace illum::bake
