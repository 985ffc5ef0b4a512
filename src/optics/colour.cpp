// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/colour.hpp"

#include "cie_tables.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace caustic::optics {
namespace {

// Table value at `nm`, linear between rows, zero outside the table.
template <typename Get>
double table_at(double nm, Get get) {
  const double f = (nm - cie::kFirstNm) / cie::kStepNm;
  if (!(f >= 0) || f > cie::kSamples - 1) return 0;
  const int i = std::min(static_cast<int>(f), cie::kSamples - 2);
  const double t = f - i;
  return get(i) * (1 - t) + get(i + 1) * t;
}

double gaussian(double nm, double centre, double fwhm) {
  const double u = (nm - centre) / fwhm;
  return std::exp(-4 * std::log(2.0) * u * u);
}

// Planck's law without its constant factor: λ^-5 / (exp(c2 / λT) - 1), with
// the CIE's c2 = 1.4388e-2 m·K (CIE 015:2018), λ in nm.
double planck(double nm, double kelvin) {
  constexpr double c2_nm_k = 1.4388e7;
  return std::pow(nm * 1e-3, -5.0) / std::expm1(c2_nm_k / (nm * kelvin));
}

// Sum over 1 nm steps of power * cmf in [from, to), every band sharing the
// same grid so that the bands add up to the whole.
Xyz integrate(const LightSpectrum& light, int from_nm, int to_nm) {
  Xyz sum;
  for (int nm = from_nm; nm < to_nm; ++nm) {
    const double s = power(light, nm + 0.5);
    const Xyz c = cie1931(nm + 0.5);
    sum.x += s * c.x;
    sum.y += s * c.y;
    sum.z += s * c.z;
  }
  return sum;
}

}  // namespace

Xyz cie1931(double nm) {
  const auto& t = cie::kObserver1931;
  return {table_at(nm, [&](int i) { return t[i].x; }), table_at(nm, [&](int i) { return t[i].y; }),
          table_at(nm, [&](int i) { return t[i].z; })};
}

std::array<double, 2> chromaticity(const Xyz& c) {
  const double sum = c.x + c.y + c.z;
  if (sum == 0) return {0, 0};
  return {c.x / sum, c.y / sum};
}

Rgb linear_srgb(const Xyz& c) {
  return {3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
          0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
}

Xyz xyz(const Rgb& c) {
  return {0.4124 * c.r + 0.3576 * c.g + 0.1805 * c.b, luminance(c), 0.0193 * c.r + 0.1192 * c.g + 0.9505 * c.b};
}

double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

double power(const LightSpectrum& light, double nm) {
  switch (light.kind) {
    case Illuminant::d65: return table_at(nm, [](int i) { return cie::kD65[i]; });
    case Illuminant::equal: return 1.0;
    case Illuminant::blackbody: return planck(nm, light.kelvin);
    case Illuminant::led: return gaussian(nm, 450, 20) + 0.6 * gaussian(nm, 560, 120);
  }
  return 0;
}

Xyz tristimulus(const LightSpectrum& light) {
  return integrate(light, static_cast<int>(kVisibleMinNm), static_cast<int>(kVisibleMaxNm));
}

std::vector<WavelengthSample> wavelength_samples(const LightSpectrum& light, int k) {
  if (k < 1 || k > kMaxWavelengths)
    throw std::invalid_argument("wavelength samples must be 1 to " + std::to_string(kMaxWavelengths));
  if (light.kind == Illuminant::blackbody && !(light.kelvin >= 1000 && light.kelvin <= 40000))
    throw std::invalid_argument("a blackbody needs a temperature of 1000 to 40000 K");
  const Rgb white = linear_srgb(tristimulus(light));
  std::vector<WavelengthSample> samples;
  const int span = static_cast<int>(kVisibleMaxNm - kVisibleMinNm);
  for (int i = 0; i < k; ++i) {
    // Band edges on whole nanometres so the bands tile the 1 nm grid exactly.
    const int from = static_cast<int>(kVisibleMinNm) + span * i / k;
    const int to = static_cast<int>(kVisibleMinNm) + span * (i + 1) / k;
    const Rgb c = linear_srgb(integrate(light, from, to));
    samples.push_back({0.5 * (from + to), double(from), double(to), {c.r / white.r, c.g / white.g, c.b / white.b}});
  }
  return samples;
}

}  // namespace caustic::optics
