// The identity of a scene's geometry, recorded by every bake folder and checked by its
// readers, so that baked data is never shown on a scene it was not baked for.
//
// geometry_hash(scene) is a 64-bit hash (splitmix64 finaliser chained over 64-bit words,
// core/rng.h hash_mix) of, in this order:
//   the mesh count; per mesh: vertex count, then per vertex the bit patterns of its
//     position, normal and tangent (xyzw; none when the mesh has no tangents) and uv1 (none
//     when it has none), then the index count and every index;
//   the instance count; per instance: its mesh index and the 16 bit patterns of its
//     object-to-world transform (column-major).
// What the baked texels depend on for their place and their frame: positions and indices
// (where a texel is), transforms (a bake is of world-space surfaces: moving, turning or
// scaling an instance changes the light it receives and, since charts are built in world
// space, the atlas too, so the same meshes under other transforms are another scene),
// normals and tangents (the frame RNM and SH layers are expressed in) and uv1 (a light-map
// bake hashes its scene after its atlas is applied, so uv1 is the atlas's and the hash also
// ties atlas.bin to the bake). Not hashed: uv0, materials, lights, camera, names — they change
// what the light is, not where it was baked; re-baking after such an edit is the user's call.
// Bit patterns, not values: no arithmetic, so every build (compilers, flags, sanitizers)
// computes the same hash for the same loaded scene (−0 and +0 differ; NaN cannot occur in
// a loaded scene).
#pragma once

#include <cstdint>
#include <string>

#include "illum/scene/scene.h"

namespace illum {

uint64_t geometry_hash(const Scene& scene);
// 16 lowercase hex digits, as bake manifests record it.
std::string geometry_hash_hex(const Scene& scene);

}  // namespace illum
