// Where the light propagation volume's cascades lie (lpv.cpp, docs/realtime-lpv.md): nested
// boxes of n³ cells around the camera, the cell size doubling from one to the next, each
// snapped to its own cell size so that none crawls as the camera moves.
#pragma once

#include <vector>

#include "illum/core/math.h"

namespace illum::realtime {

struct LpvCascade {
  vec3 lo{0.0f};      // the box's min corner, a multiple of `cell` on each axis
  float cell = 1.0f;  // cell size, world units
};

// A cascade's light fades into the next coarser one's over this many of its cells, measured
// from the centres of its outermost cells (shaders/lpv_resolve.comp: weight min(i/2, 1) for
// the cell i cells from the outermost layer).
constexpr float kLpvBlendCells = 2.0f;
// A cascade's centre is kept this many cells of the next coarser cascade inside that one's box,
// so that wherever the finer one blends, the coarser one is at full weight.
constexpr float kLpvNestCells = 3.0f;

// `count` cascades of n cells a side, finest first. cell > 0: the finest cascade's cell size,
// the coarsest centred on the camera. cell = 0: the coarsest spans `scene` (n − 1 cells its
// largest side), fixed. Each finer cascade, of half the cell size, is centred on the camera
// clamped kLpvNestCells inside the coarser box, then snapped to its own cell size.
std::vector<LpvCascade> lpv_cascades(const vec3& camera, int n, int count, float cell,
                                     const Bounds3& scene);

// Cells from p to cascade c's box, measured from its outermost cells' centres (negative
// outside): the distance the lookup's blend weight ramps over.
float lpv_inside_cells(const LpvCascade& c, int n, const vec3& p);

}  // namespace illum::realtime
