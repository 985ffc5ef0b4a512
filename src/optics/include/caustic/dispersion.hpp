// SPDX-License-Identifier: LGPL-2.1-or-later
// Refractive index against wavelength: the first piece of spectral light
// (several wavelengths a frame, each traced with its own index). Materials
// that glass makers and the optics literature describe come as Sellmeier
// sums with their sources (materials()); a scene's own coefficients may use
// Cauchy's law instead.
//
// Conventions:
//  - wavelengths in nanometres, as the sources state them: the catalogue
//    lines below are wavelengths in standard air, as colour.hpp's are;
//    vacuum wavelengths are 0.03 % longer, which moves an index of these
//    materials by at most 5e-5 in the visible (polycarbonate at 380 nm),
//    below what a caustic shows. The laws' own unit, the
//    micrometre, stays inside index();
//  - an index is what its source gives: glass catalogues (Schott) quote n
//    relative to air, Malitson and Daimon & Masumura absolute to vacuum.
//    The two differ by air's 1.0003 (0.03 %), below what a caustic shows;
//  - outside a law's measured range index() still answers (the formulas
//    extrapolate smoothly in the visible and near UV/IR); valid() says
//    whether a wavelength is inside it.
#pragma once

#include <array>
#include <span>
#include <string_view>

namespace caustic::optics {

/// n² − 1 = Σ b_k λ² / (λ² − c_k), λ in µm, c_k in µm². Unused terms are 0.
struct Sellmeier {
  std::array<double, 4> b{}, c{};
  bool operator==(const Sellmeier&) const = default;
};

/// n = a + b / λ², λ in µm: two coefficients for a material given by hand
/// (a: the index far in the red; b: its dispersion, about 0.004 for crown
/// glass, 0.01 for flint).
struct Cauchy {
  double a = 1.5, b = 0.0;
  bool operator==(const Cauchy&) const = default;
};

/// The Fraunhofer lines by which catalogues state n and the Abbe number:
/// helium d (587.5618 nm), hydrogen F (486.1327 nm) and C (656.2725 nm).
inline constexpr double kLineD = 587.5618, kLineF = 486.1327, kLineC = 656.2725;

/// A material by name, its law, where the law holds, and who measured it.
struct Medium {
  std::string_view name;
  Sellmeier law;
  double min_nm, max_nm;  ///< the range of the measurements the law fits
  std::string_view source;
};

/// Every named material, one table for all users (scene keys, docs, tests).
std::span<const Medium> materials();
/// The material called `name`, if any.
const Medium* find_material(std::string_view name);

/// The index at `nm`. Throws std::invalid_argument for a wavelength that is
/// not positive or sits on a pole of the law (λ² = c_k).
double index(const Sellmeier& law, double nm);
double index(const Cauchy& law, double nm);

/// Whether `nm` lies in the range where `m` was measured.
inline bool valid(const Medium& m, double nm) { return nm >= m.min_nm && nm <= m.max_nm; }

/// Abbe number V_d = (n_d − 1) / (n_F − n_C): large for little dispersion
/// (crown glass about 64, flint 30 and below).
template <typename Law>
double abbe_number(const Law& law) {
  return (index(law, kLineD) - 1.0) / (index(law, kLineF) - index(law, kLineC));
}

}  // namespace caustic::optics
