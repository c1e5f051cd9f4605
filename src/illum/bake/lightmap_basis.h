// The light-map bases and contents both bakers write (lightmap_baker.h, radiosity_baker.h)
// and the real-time renderer reads; the layers' meanings are in lightmap_baker.h.
#pragma once

#include <string>

#include "illum/core/math.h"

namespace illum::bake {

enum class LightmapBasis { kPlain, kRnm, kShL1 };
// Which light the map holds. kAll: everything (the real-time renderer then adds no
// per-light shading). kIndirect: everything except the direct light of point, spot and
// directional lights at the texel, which the real-time renderer adds per pixel with its
// shadows ("mixed" lighting); area and environment light stay in the map, direct and
// indirect.
enum class LightmapContent { kAll, kIndirect };

const char* to_string(LightmapBasis basis);
const char* to_string(LightmapContent content);
LightmapBasis lightmap_basis_from_string(const std::string& name);      // plain|rnm|sh
LightmapContent lightmap_content_from_string(const std::string& name);  // all|indirect
int layer_count(LightmapBasis basis);

// Source engine's radiosity normal mapping basis in tangent space (S003 ch. 7).
inline constexpr float kRnmBasis[3][3] = {{0.816496581f, 0.0f, 0.577350269f},
                                          {-0.408248290f, 0.707106781f, 0.577350269f},
                                          {-0.408248290f, -0.707106781f, 0.577350269f}};

// Each layer's basis function for a unit direction w above a texel with unit normal n and
// tangent frame (t, b): plain cos/π; rnm max(b_i·w, 0)/π; sh the SH-L1 functions of w in
// tangent space (x = t, y = b, z = n). `out` gets layer_count(basis) values.
void basis_weights(LightmapBasis basis, const vec3& w, const vec3& n, const vec3& t, const vec3& b,
                   float* out);

}  // namespace illum::bake
