// Precomputed irradiance for final gathering (Christensen, "Faster Photon Map Global
// Illumination", JGT 1999; Jensen 2001 §7.5): the irradiance estimate of the global map is
// computed once at every `stride`-th photon and stored there, so a final-gather ray that
// ends on a Lambertian surface costs one nearest-point lookup instead of a k-nearest
// density estimate (k = 100 by default). With 16 gather rays per camera sample the
// k-nearest queries were 85 % of a Cornell-box render (profile in docs/photon-mapping.md).
//
// Approximation (bias, on top of the density estimate's own): the irradiance at a gather
// hit y is read from the nearest stored point, which lies within about the photon spacing
// of y; the error is that of a piecewise-constant interpolation over the points. It is seen
// only through one diffuse bounce and averaged over the gather rays. Non-Lambertian gather
// hits (Phong, Blinn) keep the full estimate, as the irradiance alone cannot give them.
#pragma once

#include <optional>
#include <vector>

#include "illum/render/bsdf.h"
#include "illum/render/photon_map.h"

namespace illum {

// Every stored point is a Photon whose `power` holds the irradiance E (W/m² per channel)
// arriving on the side of `normal` given by `wi` (wi = ±normal), estimated from the global
// map's photons on that side within the k-nearest (bounded by max_radius) disc, leaving out
// the photon the point sits on (so the k-NN bias is that of k − 1 photons).
PhotonMap precompute_irradiance(const PhotonMap& global, int stride, int k, float max_radius,
                                const FilterSettings& filter);

// Irradiance at p (geometric normal ng) on the side of wo, from the nearest point of
// `irradiance` within max_radius whose normal agrees with ng and that was lit on wo's side;
// nullopt when none of the few nearest qualifies (the caller falls back to the full estimate).
std::optional<Color> lookup_irradiance(const PhotonMap& irradiance, const vec3& p, const vec3& ng,
                                       const vec3& wo, float max_radius,
                                       std::vector<PhotonNeighbor>* scratch);

}  // namespace illum
