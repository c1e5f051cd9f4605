// Stencil shadow volumes (S002 §4.3, ALGORITHMS.md 23), built on the CPU: per light, the
// caster triangles (those facing the light, or with the seed's back-facing-caster option
// those facing away) are closed into volumes with a front cap, a back cap projected to
// infinity (w = 0) and side quads only on silhouette edges — edges whose neighbour across
// (found through position-welded adjacency) is not a caster. Every face is wound outward,
// so the z-fail ("Carmack's reverse") stencil count is exact with two-sided stencil.
// Triangles of open meshes (single-sided walls, boxes without bottoms) always cast: a
// facing test cannot tell which side of an open surface is "inside", and a volume from a
// triangle reoriented towards the light is correct either way.
#pragma once

#include <cstdint>
#include <vector>

#include "illum/scene/scene.h"

namespace illum::realtime {

struct ShadowVolumeStats {
  size_t caster_triangles = 0;
  size_t silhouette_edges = 0;
  size_t volume_triangles = 0;
  double build_ms = 0.0;  // CPU time of the last build
};

class ShadowVolumeBuilder {
 public:
  // Welds vertices and builds edge adjacency for every instance (world space) once.
  explicit ShadowVolumeBuilder(const Scene& scene);

  // Volume triangles for `light` as homogeneous vertices (xyz, w ∈ {0, 1}), 3 per triangle.
  // `back_facing_casters` uses the triangles facing away from the light as casters.
  // `cap_offset` pushes the front cap away from the light (world units) against z-fighting
  // between the cap and the caster's own surface.
  void build(const Light& light, bool back_facing_casters, float cap_offset,
             std::vector<glm::vec4>* out, ShadowVolumeStats* stats) const;

  // A caster triangle with its adjacency (world space). The GPU extraction
  // (shaders/silhouettes.comp) uploads these and applies the same rules as build().
  struct Triangle {
    vec3 p[3];
    uint32_t v[3];         // welded vertex ids
    int32_t neighbour[3];  // triangle across edge (v[k], v[k+1]); −1 boundary, −2 non-manifold
    // The neighbour across edge k runs it the same way (v[k] → v[k+1]) in its own winding.
    bool same_direction[3] = {false, false, false};
    bool open = false;  // its instance is not a closed mesh: casts whichever way it faces
  };
  const std::vector<Triangle>& triangles() const { return triangles_; }
  size_t triangle_count() const { return triangles_.size(); }

 private:
  std::vector<Triangle> triangles_;
};

}  // namespace illum::realtime
