// Relighting an SHL-map's texels under a new distant light (S002 §5.5): per texel the RGB value
// Σ_i T_i L_i (E/π before the albedo, prt_baker.h), written as 3 floats a texel — what a game
// does each time its sun or sky changes, turning the baked transfer into a light-map. Three
// storage forms of the transfer, by the bytes a texel costs to read at 4 bands:
//   fp32  3·n² floats (192 bytes),
//   fp16  3·n² halves (96 bytes; a relative rounding error of at most 2⁻¹¹ per coefficient),
//   VQ    a 16-bit index (2 bytes) into a codebook relit once per light (prt_vq.h).
// The loops are memory-bound: bench/suites/bench_prt.cpp times them against the machine's
// bandwidth.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "illum/bake/prt_relight.h"
#include "illum/bake/prt_vq.h"

namespace illum::bake {

// IEEE half-precision copies of transfer vectors (round to nearest even; values beyond the
// half range become ±inf, which the callers' finite checks catch).
std::vector<uint16_t> to_half(std::span<const float> values);
float half_to_float(uint16_t h);

// `transfer` holds texels × 3·bands² values laid out [texel][i][rgb]; `out` 3 floats a texel.
// Throws Error when the light's band count differs from `bands` or the sizes disagree.
void relight_texels(std::span<const float> transfer, int bands, const ShLight& light,
                    std::span<float> out);
void relight_texels(std::span<const uint16_t> half_transfer, int bands, const ShLight& light,
                    std::span<float> out);
// Relights the codebook's representatives, then gives each texel its representative's value:
// `out` has 3 floats for each of codebook.indices.
void relight_texels(const VqCodebook& codebook, int bands, const ShLight& light,
                    std::span<float> out);

}  // namespace illum::bake
