// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/dispersion.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace caustic::optics {
namespace {

// Coefficients as their sources print them (c_k in µm²; Malitson gives
// the resonance wavelengths, squared here).
constexpr Medium kMaterials[] = {
    {"bk7",
     {{1.03961212, 0.231792344, 1.01046945, 0.0}, {0.00600069867, 0.0200179144, 103.560653, 0.0}},
     300.0,
     2500.0,
     "SCHOTT optical glass data sheet N-BK7 (Sellmeier coefficients; n relative to air)"},
    {"fused_silica",
     {{0.6961663, 0.4079426, 0.8974794, 0.0}, {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161, 0.0}},
     210.0,
     3710.0,
     "I. H. Malitson, Interspecimen comparison of the refractive index of fused silica, "
     "J. Opt. Soc. Am. 55, 1205-1209 (1965)"},
    {"pmma",
     {{1.1819, 0.0, 0.0, 0.0}, {0.011313, 0.0, 0.0, 0.0}},
     437.0,
     1052.0,
     "N. Sultanova, S. Kasarova, I. Nikolov, Dispersion properties of optical polymers, "
     "Acta Physica Polonica A 116, 585-587 (2009)"},
    {"polycarbonate",
     {{1.4182, 0.0, 0.0, 0.0}, {0.021304, 0.0, 0.0, 0.0}},
     437.0,
     1052.0,
     "N. Sultanova, S. Kasarova, I. Nikolov, Dispersion properties of optical polymers, "
     "Acta Physica Polonica A 116, 585-587 (2009)"},
    {"water",
     {{5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1},
      {5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1}},
     182.0,
     1129.0,
     "M. Daimon, A. Masumura, Measurement of the refractive index of distilled water from the near-infrared "
     "region to the ultraviolet region, Appl. Opt. 46, 3811-3820 (2007), at 20 degrees C; n absolute"},
};

double micrometres(double nm) {
  if (!(nm > 0.0) || !std::isfinite(nm))
    throw std::invalid_argument("wavelength must be a positive number of nanometres, got " + std::to_string(nm));
  return nm / 1000.0;
}

}  // namespace

std::span<const Medium> materials() { return kMaterials; }

const Medium* find_material(std::string_view name) {
  for (const Medium& m : kMaterials)
    if (m.name == name) return &m;
  return nullptr;
}

double index(const Sellmeier& law, double nm) {
  const double l = micrometres(nm), l2 = l * l;
  double n2 = 1.0;
  for (std::size_t k = 0; k < law.b.size(); ++k) {
    if (law.b[k] == 0.0) continue;
    const double denominator = l2 - law.c[k];
    if (denominator == 0.0) throw std::invalid_argument("wavelength " + std::to_string(nm) + " nm sits on a pole of the law");
    n2 += law.b[k] * l2 / denominator;
  }
  // Between a pole and the next the sum can fall below -1 (absorption
  // bands the law does not model): no real index there.
  if (!(n2 > 0.0)) throw std::invalid_argument("no real index at " + std::to_string(nm) + " nm");
  return std::sqrt(n2);
}

double index(const Cauchy& law, double nm) {
  const double l = micrometres(nm);
  return law.a + law.b / (l * l);
}

}  // namespace caustic::optics
