// Named metals for conductor materials: complex refractive index η + iκ per RGB channel.
//
// Source: Palik, "Handbook of Optical Constants of Solids" (1985), as tabulated by the
// luxpop.com database (the tables Mitsuba ships as data/ior/{Au,Cu,Ag,Al}.{eta,k}.spd).
// RGB: the mean of n and of k over box bands, linearly interpolated between the tabulated
// wavelengths on a 0.1 nm grid — R 600–700 nm, G 500–600 nm, B 400–500 nm. Their
// normal-incidence reflectances ((n−1)² + κ²)/((n+1)² + κ²): gold (0.943, 0.811, 0.396),
// copper (0.933, 0.667, 0.551), silver (0.970, 0.960, 0.919), aluminium (0.911, 0.920,
// 0.924) (tests/render/microfacet_test.cpp checks them).
#pragma once

#include <optional>
#include <string_view>

#include "illum/core/color.h"

namespace illum {

struct ComplexIndex {
  Color eta, k;
};

inline constexpr const char* kMetalNames = "gold, copper, silver, aluminium";

inline std::optional<ComplexIndex> named_metal(std::string_view name) {
  if (name == "gold") return ComplexIndex{{0.1761f, 0.4119f, 1.4178f}, {3.3022f, 2.5953f, 1.8808f}};
  if (name == "copper")
    return ComplexIndex{{0.2427f, 0.8756f, 1.1624f}, {3.6046f, 2.6449f, 2.3807f}};
  if (name == "silver")
    return ComplexIndex{{0.1363f, 0.1251f, 0.1501f}, {4.1272f, 3.3367f, 2.4620f}};
  if (name == "aluminium" || name == "aluminum")
    return ComplexIndex{{1.4869f, 0.9672f, 0.6217f}, {7.7954f, 6.6799f, 5.4706f}};
  return std::nullopt;
}

}  // namespace illum
