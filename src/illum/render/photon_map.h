// Photon storage and nearest-neighbour search (Jensen, "Realistic Image Synthesis Using
// Photon Mapping", ch. 6): a left-balanced kd-tree in implicit (heap) layout, built in
// O(n log n) with nth_element, with k-nearest-neighbour (bounded max-heap) and fixed-radius
// queries, plus the density estimates of S004 post 2, L_r = (1/πr²)·Σ f_r·φ_p, with the
// cone and Gaussian filters.
//
// Why our own tree and not nanoflann: `illum-bench photons` measures both on the same
// points (see bench/suites/bench_photons.cpp and render/README.md for the numbers); the implicit
// tree needs no node pointers, keeps positions in a dense array in traversal order and
// was the faster of the two for the photon-gather queries we run.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "illum/core/color.h"
#include "illum/core/math.h"

namespace illum {

struct Photon {
  vec3 position{0.0f};
  vec3 wi{0.0f, 0.0f, 1.0f};      // unit direction towards where the photon came from
  Color power{0.0f};              // flux in W per channel; negative for shadow photons
  vec3 normal{0.0f, 0.0f, 1.0f};  // geometric normal of the surface it was stored on
};

// One neighbour found by a query: index into PhotonMap::photons() and squared distance.
struct PhotonNeighbor {
  uint32_t index;
  float distance2;
};

class PhotonMap {
 public:
  PhotonMap() = default;
  // Builds the tree over `photons` (reordered into tree order; their order is not kept).
  explicit PhotonMap(std::vector<Photon> photons);

  size_t size() const { return photons_.size(); }
  bool empty() const { return photons_.empty(); }
  std::span<const Photon> photons() const { return photons_; }
  const Photon& photon(uint32_t i) const { return photons_[i]; }
  Bounds3 bounds() const { return bounds_; }

  // The up-to-k nearest photons within `max_distance` of p, written to `out` (cleared
  // first) sorted by increasing distance. Returns the squared distance of the farthest
  // one kept (0 if none).
  float knn(const vec3& p, int k, float max_distance, std::vector<PhotonNeighbor>* out) const;

  // Calls fn(index, distance2) for every photon within `radius` of p (no order).
  template <typename Fn>
  void for_each_in_radius(const vec3& p, float radius, Fn&& fn) const;

  // Same as for_each_in_radius, collecting into `out` (cleared first).
  void radius_search(const vec3& p, float radius, std::vector<PhotonNeighbor>* out) const;

 private:
  std::vector<Photon> photons_;  // in heap order: children of node i are 2i+1 and 2i+2
  std::vector<vec3> positions_;  // copy of photon positions, dense for the traversal
  std::vector<uint8_t> axis_;    // split axis per node
  Bounds3 bounds_;
};

// Kernels for the density estimate. Weights are functions of the distance d to the query
// point and the gather radius r, and every kernel is divided by its integral over the
// disc so that a constant photon density is reproduced without bias.
enum class PhotonFilter { kNone, kCone, kGaussian };

PhotonFilter parse_photon_filter(const std::string& name);  // "none" | "cone" | "gaussian"

struct FilterSettings {
  PhotonFilter type = PhotonFilter::kCone;
  float cone_k = 1.1f;         // Jensen's cone constant k ≥ 1: w = 1 − d/(k·r)
  float gauss_alpha = 0.918f;  // Jensen's Gaussian constants (Pavicic 1990)
  float gauss_beta = 1.953f;
};

// Weight of a photon at squared distance d2 within gather radius² r2 (unnormalized).
float filter_weight(const FilterSettings& filter, float d2, float r2);
// ∫ weight dA over the disc of radius r, divided by π r²: the normalization the estimate
// divides by (1 for none, 1 − 2/(3k) for the cone, computed in closed form for the Gaussian).
float filter_normalization(const FilterSettings& filter);

// Reflected radiance from a photon map around a surface point:
//   L_r = Σ f_r(p)·φ_p·w(d_p) / (π r² · norm),
// where r is the distance of the k-th nearest photon (bounded by max_radius), or, for
// k ≤ 0, the fixed radius max_radius. `brdf(photon)` returns f_r for the photon's wi (and
// may return 0 to reject it, e.g. photons on a surface facing away); `scratch` avoids
// allocation per call.
template <typename Brdf>
Color estimate_radiance(const PhotonMap& map, const vec3& p, int k, float max_radius,
                        const FilterSettings& filter, Brdf&& brdf,
                        std::vector<PhotonNeighbor>* scratch);

// ---------------------------------------------------------------------------------------
// Template implementations.

template <typename Fn>
void PhotonMap::for_each_in_radius(const vec3& p, float radius, Fn&& fn) const {
  const uint32_t n = static_cast<uint32_t>(positions_.size());
  if (n == 0) return;
  const float r2 = radius * radius;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const uint32_t node = stack[--top];
    const vec3& q = positions_[node];
    const vec3 d = p - q;
    const float d2 = glm::dot(d, d);
    if (d2 <= r2) fn(node, d2);
    const uint32_t left = 2 * node + 1;
    if (left >= n) continue;
    const int axis = axis_[node];
    const float delta = p[axis] - q[axis];
    const uint32_t near = delta <= 0.0f ? left : left + 1;
    const uint32_t far = delta <= 0.0f ? left + 1 : left;
    if (far < n && delta * delta <= r2) stack[top++] = far;
    if (near < n) stack[top++] = near;
  }
}

template <typename Brdf>
Color estimate_radiance(const PhotonMap& map, const vec3& p, int k, float max_radius,
                        const FilterSettings& filter, Brdf&& brdf,
                        std::vector<PhotonNeighbor>* scratch) {
  float r2 = max_radius * max_radius;
  if (k > 0) {
    const float far2 = map.knn(p, k, max_radius, scratch);
    if (scratch->empty()) return Color(0.0f);
    // With fewer than k photons inside max_radius the disc is the full max_radius one.
    if (static_cast<int>(scratch->size()) == k) r2 = far2;
  } else {
    map.radius_search(p, max_radius, scratch);
  }
  if (scratch->empty() || r2 <= 0.0f) return Color(0.0f);
  Color sum(0.0f);
  for (const PhotonNeighbor& nb : *scratch) {
    const Photon& ph = map.photon(nb.index);
    const Color f = brdf(ph);
    if (is_black(f)) continue;
    sum += f * ph.power * filter_weight(filter, nb.distance2, r2);
  }
  return sum / (kPi * r2 * filter_normalization(filter));
}

}  // namespace illum
