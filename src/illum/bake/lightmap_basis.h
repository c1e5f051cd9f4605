// The light-map bases and contents both bakers write (lightmap_baker.h, radiosity_baker.h)
// and the real-time renderer reads; the layers' meanings are in lightmap_baker.h.
#pragma once

#include <string>
#include <vector>

#include "illum/core/image.h"
#include "illum/core/math.h"

namespace illum::bake {

// kDominant (3 layers, tangent space, derived from the SH-L1 sums after the bake:
// dominant_from_sh): 0 ambient A, 1 directional colour C, 2 dominant direction d (unit,
// x = t, y = b, z = n); shown as E/π(n) = A + C·max(0, n·d).
enum class LightmapBasis { kPlain, kRnm, kShL1, kDominant };
// Which light the map holds. kAll: everything (the real-time renderer then adds no
// per-light shading). kIndirect: everything except the direct light of point, spot and
// directional lights at the texel, which the real-time renderer adds per pixel with its
// shadows ("mixed" lighting); area and environment light stay in the map, direct and
// indirect.
enum class LightmapContent { kAll, kIndirect };

const char* to_string(LightmapBasis basis);
const char* to_string(LightmapContent content);
LightmapBasis lightmap_basis_from_string(const std::string& name);      // plain|rnm|sh|dominant
LightmapContent lightmap_content_from_string(const std::string& name);  // all|indirect
int layer_count(LightmapBasis basis);
// The basis the bakers accumulate samples in: the basis itself, SH-L1 for kDominant (its
// layers are not linear in the light, so they are made from the SH-L1 sums at the end).
LightmapBasis accumulation_basis(LightmapBasis basis);

// Source engine's radiosity normal mapping basis in tangent space (S003 ch. 7).
inline constexpr float kRnmBasis[3][3] = {{0.816496581f, 0.0f, 0.577350269f},
                                          {-0.408248290f, 0.707106781f, 0.577350269f},
                                          {-0.408248290f, -0.707106781f, 0.577350269f}};

// Each layer's basis function for a unit direction w above a texel with unit normal n and
// tangent frame (t, b): plain cos/π; rnm max(b_i·w, 0)/π; sh the SH-L1 functions of w in
// tangent space (x = t, y = b, z = n); dominant as sh. `out` gets
// layer_count(accumulation_basis(basis)) values.
void basis_weights(LightmapBasis basis, const vec3& w, const vec3& n, const vec3& t, const vec3& b,
                   float* out);

// The dominant-direction layers from the four SH-L1 layers (radiance coefficients c0..c3,
// tangent space, as the bakers write them), texel by texel:
//   d  = the luminance-weighted mean incident direction: the luminance of the band-1 vector
//        (c3, c1, c2) ∝ ∫ L(ω) ω dω, normalised (the normal where it vanishes);
//   E0 = E/π on the baked normal, exact from the SH sums: every direction a texel receives
//        lies in its upper hemisphere, where z = Y10/√(3/4π), so E0 = c2/(π√(3/4π)) — the
//        plain basis's quantity, estimated from the same samples;
//   f  = the directional fraction per channel, 2r − 1 clamped to [0, 1] with
//        r = (v·d)/s, s = c0/Y00 = ∫L dω and v = band-1/√(3/4π) = ∫L ω dω: r = 1 for light
//        from the single direction d, ½ for a uniform hemisphere (all ambient);
//        scaled by min(1, d_z/kMinDirectionZ) so C stays bounded for grazing light;
//   C  = f·E0/max(d_z, kMinDirectionZ), A = E0 − C·d_z.
// So A + C·d_z = E0 exactly on the baked normal: the display (A + C·max(0, n·d)) shows the
// plain map where there is no normal map. Throws Error unless given 4 equal-sized layers.
inline constexpr float kMinDirectionZ = 0.05f;
std::vector<Image> dominant_from_sh(const std::vector<Image>& sh);

}  // namespace illum::bake
