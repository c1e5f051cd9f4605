// Ray queries over a Scene with Embree 3: one triangle geometry per mesh instance
// (vertices pre-transformed to world space, geometry id = instance index).
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "illum/core/math.h"
#include "illum/scene/scene.h"

namespace illum {

inline constexpr uint32_t kInvalidId = 0xffffffffu;

// What a closest-hit query returns; cheap to copy.
struct Hit {
  float t = kInf;
  uint32_t instance = kInvalidId;
  uint32_t primitive = kInvalidId;  // triangle index within the instance's mesh
  vec2 barycentric{0.0f};           // (b1, b2): p = (1−b1−b2)·v0 + b1·v1 + b2·v2
  bool valid() const { return instance != kInvalidId; }
};

// Everything a shader needs at a hit point, in world space.
struct SurfaceInteraction {
  vec3 p{0.0f};
  vec3 ng{0.0f, 0.0f, 1.0f};  // unit geometric normal, from the triangle's winding
  // Unit shading normal (interpolated, normal-mapped, bent towards ng where it would hide wo:
  // ray_tracer.cpp bent_for_valid_reflection), on ng's side.
  vec3 ns{0.0f, 0.0f, 1.0f};
  Frame shading;  // tangent frame around ns (t follows the mesh tangent if any)
  vec2 uv0{0.0f}, uv1{0.0f};
  vec3 wo{0.0f};  // unit direction towards the ray origin
  float t = 0.0f;
  uint32_t instance = kInvalidId, primitive = kInvalidId;
  int material = -1;  // index into Scene::materials
  int light = -1;     // index into Scene::lights when the surface is an area light, else −1
};

// Builds the BVH in the constructor (throws illum::Error on a malformed scene or an Embree
// error); keeps a reference to `scene`, which must outlive it. All queries are const and
// safe to call from any number of threads at once.
class RayTracer {
 public:
  explicit RayTracer(const Scene& scene);
  ~RayTracer();
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  // Closest hit along ray.tmin..ray.tmax. Returns false (and leaves *hit invalid) on a miss.
  bool intersect(const Ray& ray, Hit* hit) const;
  // Any hit along ray.tmin..ray.tmax (shadow rays).
  bool occluded(const Ray& ray) const;
  // Batches: Embree ray streams (rtcIntersect1M / rtcOccluded1M); results in order.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  void occluded(std::span<const Ray> rays, std::span<uint8_t> blocked) const;

  // Fills the surface description for a valid hit of `ray` (texture lookups for normal maps
  // included).
  SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const;

  const Scene& scene() const { return scene_; }
  Bounds3 bounds() const;
  // Raw Embree handle (RTCScene) for benchmarks that compare against plain Embree loops.
  void* embree_scene() const;

 private:
  struct Impl;
  const Scene& scene_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace illum
