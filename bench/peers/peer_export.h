// Writes an illum scene, as illum loaded it, for a peer renderer's import script
// (bench/peers/): a JSON file (camera, materials, lights in the peer's units, settings) and a
// binary file of world-space triangles. Exporting what illum's loader produced — after
// scaling, hidden objects, instance transforms, computed normals and the OBJ's flipped v —
// rather than handing the peer the original files means both renderers see the same
// triangles, normals and texture coordinates; see bench/peers/README.md for the format.
#pragma once

#include <string>

namespace illum {
struct Camera;
struct Scene;
}  // namespace illum

namespace illum::bench {

struct PeerRenderSettings {
  int width = 0, height = 0;
  int max_bounces = 8;  // illum's count; the file carries the peer's too
};

// Writes `stem`.json and `stem`.bin (stem: a path without extension). Throws illum::Error for
// what the Cycles peer cannot reproduce (material types other than Lambert and mirror,
// environment maps, area lights that are not emissive meshes) and on write failure.
void export_peer_scene(const Scene& scene, const Camera& camera, const PeerRenderSettings& settings,
                       const std::string& stem);

}  // namespace illum::bench
