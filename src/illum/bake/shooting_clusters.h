// Receiver clusters for progressive shooting (progressive_shooting.h): a binary tree over the
// patches' positions, so that a shot tests visibility once per far cluster instead of once
// per receiver texel (one ray per receiver made a shot O(N) rays and the
// whole bake O(N²) rays).
//
// A shot visits the tree from a fixed cut of subtrees (the parallel tasks). A far cluster
// (its box beyond the near-field distance, so no member of the shooting group and no
// receiver the group's members shoot one by one is inside) is skipped when its box lies
// wholly behind the source's plane. It *shares* visibility when its half-diagonal r is at
// most `ratio` × the distance d from the source to its centre (it subtends a cone of
// half-angle ≤ asin(ratio) seen from the source: a solid-angle oracle, as Hanrahan's
// hierarchical refinement) and its probes agree. Every member first gets its own unoccluded
// form factor (the same arithmetic as without clusters); only members facing the source
// (factor > 0) need a verdict: when there are at most kClusterOwnRays of them they get their
// own rays, else the probes are the facing members farthest along each of the box's eight
// diagonal directions (the cluster's corners; a planar cluster has four distinct ones).
// Probes that all agree give every member their verdict; probes that disagree mean a shadow
// edge crosses the cluster, which is refined into its children, down to leaves whose
// members get their own rays. Without
// occluders the result is therefore the unclustered one exactly. A straight shadow edge
// across an axis-aligned rectangular block of receivers always separates two of its corners (a
// linear function's extremes over a rectangle are at corners), so it is refined to the
// texel too; a receiver can be misjudged only when the edge bends between all the probes (a
// small occluder seen inside a cluster, a shadow's corner) or the cluster is not such a grid.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "illum/core/math.h"

namespace illum::bake {

inline constexpr int kClusterProbes = 8;    // one per diagonal of the box (duplicates skipped)
inline constexpr int kClusterOwnRays = 4;   // at most this many facing members: their own rays
inline constexpr int kClusterLeafSize = 4;  // a leaf's probes are all of its receivers
// The parallel tasks: subtrees at a depth where they hold at least kClusterTaskPatches
// patches (clusters above the cut are never shared, so the cut must not be deep), at most
// 2^kClusterMaxTaskDepth of them.
inline constexpr int kClusterTaskPatches = 2048;
inline constexpr int kClusterMaxTaskDepth = 8;

struct ReceiverCluster {
  vec3 lo{0.0f}, hi{0.0f};     // box of the members' positions
  int32_t begin = 0, end = 0;  // range of ReceiverClusters::order
  int32_t first_child = -1;    // children first_child and first_child + 1; −1: a leaf
};

struct ReceiverClusters {
  std::vector<vec3> positions;         // by patch index
  std::vector<int32_t> order;          // patch indices, each cluster's members contiguous
  std::vector<ReceiverCluster> nodes;  // nodes[0] is the root (when there are patches)
  std::vector<int32_t> tasks;          // disjoint subtrees covering every patch once
};

// Median splits along the box's longest axis down to kClusterLeafSize patches. Deterministic:
// nth_element's result depends only on the input order and positions, and ties are broken
// by patch index.
inline ReceiverClusters build_receiver_clusters(const std::vector<vec3>& positions) {
  ReceiverClusters tree;
  const int32_t n = int32_t(positions.size());
  if (n == 0) return tree;
  tree.positions = positions;
  tree.order.resize(size_t(n));
  for (int32_t i = 0; i < n; ++i) tree.order[size_t(i)] = i;
  tree.nodes.push_back({});
  tree.nodes[0].begin = 0;
  tree.nodes[0].end = n;
  std::vector<int32_t> stack{0};
  while (!stack.empty()) {
    const int32_t node = stack.back();
    stack.pop_back();
    ReceiverCluster c = tree.nodes[size_t(node)];
    c.lo = c.hi = positions[size_t(tree.order[size_t(c.begin)])];
    for (int32_t i = c.begin; i < c.end; ++i) {
      c.lo = glm::min(c.lo, positions[size_t(tree.order[size_t(i)])]);
      c.hi = glm::max(c.hi, positions[size_t(tree.order[size_t(i)])]);
    }
    const int32_t count = c.end - c.begin;
    if (count > kClusterLeafSize) {
      const vec3 extent = c.hi - c.lo;
      const int axis =
          extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
      const int32_t mid = c.begin + count / 2;
      std::nth_element(tree.order.begin() + c.begin, tree.order.begin() + mid,
                       tree.order.begin() + c.end, [&](int32_t a, int32_t b) {
                         const float pa = positions[size_t(a)][axis],
                                     pb = positions[size_t(b)][axis];
                         return pa < pb || (pa == pb && a < b);
                       });
      c.first_child = int32_t(tree.nodes.size());
      ReceiverCluster left, right;
      left.begin = c.begin, left.end = mid, right.begin = mid, right.end = c.end;
      tree.nodes.push_back(left);
      tree.nodes.push_back(right);
      stack.push_back(c.first_child + 1);
      stack.push_back(c.first_child);
    }
    tree.nodes[size_t(node)] = c;
  }
  // Tasks: the nodes at the task depth and the leaves above it.
  int task_depth = 0;
  while (task_depth < kClusterMaxTaskDepth && (n >> (task_depth + 1)) >= kClusterTaskPatches)
    ++task_depth;
  {
    std::vector<int32_t> kept;
    std::vector<std::pair<int32_t, int32_t>> walk{{0, 0}};
    while (!walk.empty()) {
      const auto [node, depth] = walk.back();
      walk.pop_back();
      const ReceiverCluster& c = tree.nodes[size_t(node)];
      if (c.first_child < 0 || depth == task_depth) {
        kept.push_back(node);
        continue;
      }
      walk.push_back({c.first_child + 1, depth + 1});
      walk.push_back({c.first_child, depth + 1});
    }
    tree.tasks = std::move(kept);
  }
  return tree;
}

// Form factors of one shot over one task's subtree. per_receiver(i) is the unclustered
// computation of receiver i (its own factor and ray, as without clusters: 0 when hidden);
// unoccluded(i) its factor without any ray (the far-field form); visible(i) a ray from the
// source to receiver i. Writes factor[i] for every patch of the subtree; returns the rays
// cast. `ratio` ≤ 0 never shares (every receiver gets per_receiver).
template <class PerReceiver, class Unoccluded, class Visible>
int64_t cluster_factors(const ReceiverClusters& tree, int32_t task, const vec3& source,
                        const vec3& source_normal, float ratio, float near2,
                        PerReceiver&& per_receiver, Unoccluded&& unoccluded, Visible&& visible,
                        float* factor, int64_t* shared_clusters) {
  int64_t rays = 0;
  int32_t stack[64];
  int top = 0;
  stack[top++] = task;
  const vec3 abs_normal = glm::abs(source_normal);
  while (top > 0) {
    const ReceiverCluster& c = tree.nodes[size_t(stack[--top])];
    const vec3 centre = 0.5f * (c.lo + c.hi), half = 0.5f * (c.hi - c.lo);
    const vec3 outside = glm::max(glm::max(c.lo - source, source - c.hi), vec3(0.0f));
    const vec3 to_centre = centre - source;
    const bool far = glm::dot(outside, outside) >= near2;
    // Far and wholly behind the source's plane (its farthest corner in front is below it by
    // more than float rounding, so coplanar receivers are left to their own factor, which
    // is 0): no factor. Near receivers take the members' own normals: never culled here.
    const float front = glm::dot(source_normal, to_centre) + glm::dot(abs_normal, half);
    if (far && front < -1e-5f * (glm::length(to_centre) + glm::length(half))) {
      for (int32_t i = c.begin; i < c.end; ++i) factor[size_t(tree.order[size_t(i)])] = 0.0f;
      continue;
    }
    if (ratio > 0.0f && far && c.end - c.begin > kClusterOwnRays &&
        glm::dot(half, half) <= ratio * ratio * glm::dot(to_centre, to_centre)) {
      // The members' own factors first: only receivers facing the source (k > 0) need a
      // verdict, and they alone are probed. Up to kClusterOwnRays of them: their own rays.
      int32_t probes[kClusterProbes];
      float extent[kClusterProbes];
      int32_t facing = 0;
      for (int q = 0; q < kClusterProbes; ++q) probes[q] = -1, extent[q] = -kInf;
      for (int32_t i = c.begin; i < c.end; ++i) {
        const int32_t r = tree.order[size_t(i)];
        const float k = unoccluded(r);
        factor[size_t(r)] = k;
        if (!(k > 0.0f)) continue;
        ++facing;
        const vec3 d = tree.positions[size_t(r)] - centre;
        for (int q = 0; q < kClusterProbes; ++q) {  // farthest along each box diagonal
          const float e = (q & 1 ? d.x : -d.x) + (q & 2 ? d.y : -d.y) + (q & 4 ? d.z : -d.z);
          if (e > extent[q]) extent[q] = e, probes[q] = r;
        }
      }
      if (facing <= kClusterOwnRays) {
        for (int32_t i = c.begin; i < c.end; ++i) {
          const int32_t r = tree.order[size_t(i)];
          if (factor[size_t(r)] > 0.0f && !visible(r)) factor[size_t(r)] = 0.0f;
        }
        rays += facing;
        continue;
      }
      int seen = 0, probed = 0;
      for (int q = 0; q < kClusterProbes; ++q) {
        bool repeated = false;  // a planar cluster's corners answer two diagonals each
        for (int e = 0; e < q; ++e) repeated = repeated || probes[e] == probes[q];
        if (repeated) continue;
        ++probed;
        seen += visible(probes[q]) ? 1 : 0;
      }
      rays += probed;
      if (seen == 0 || seen == probed) {
        if (seen == 0)
          for (int32_t i = c.begin; i < c.end; ++i) factor[size_t(tree.order[size_t(i)])] = 0.0f;
        ++*shared_clusters;
        continue;
      }
    }
    if (c.first_child < 0) {
      for (int32_t i = c.begin; i < c.end; ++i) {
        const int32_t r = tree.order[size_t(i)];
        int64_t cast = 0;
        factor[size_t(r)] = per_receiver(r, &cast);
        rays += cast;
      }
      continue;
    }
    stack[top++] = c.first_child + 1;
    stack[top++] = c.first_child;
  }
  return rays;
}

}  // namespace illum::bake
