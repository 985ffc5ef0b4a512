// SPDX-License-Identifier: LGPL-2.1-or-later
// From wavelengths to the colour a viewer sees. A spectral frame traces K
// wavelengths, each with its own refractive index (dispersion.hpp); each
// stands for a band of the visible spectrum and adds its irradiance into
// linear RGB with that band's weight: the light's power times the CIE 1931
// colour-matching functions over the band, turned into linear sRGB, then
// white-balanced so that the K weights sum to (1, 1, 1). Light that no
// dispersion separates therefore stays exactly neutral, as a camera
// balanced to the lamp would show it, whatever K and the light.
//
// Conventions:
//  - wavelengths in nanometres, in air; the visible range is 380..780 nm,
//    where the CIE tables are given (cie_tables.cpp cites them);
//  - XYZ is unnormalised (the sum over 1 nm steps); only ratios matter;
//  - RGB is linear sRGB / Rec. 709 primaries with the D65 white
//    (IEC 61966-2-1), the colours a browser shows once gamma-encoded.
#pragma once

#include <array>
#include <vector>

namespace caustic::optics {

inline constexpr double kVisibleMinNm = 380, kVisibleMaxNm = 780;
/// The most wavelength samples a frame may trace.
inline constexpr int kMaxWavelengths = 32;

struct Xyz {
  double x = 0, y = 0, z = 0;
};
struct Rgb {
  double r = 0, g = 0, b = 0;
};

/// The CIE 1931 2-degree colour-matching functions at `nm`, linearly
/// interpolated between the 5 nm table rows (summed in 1 nm steps, ȳ
/// integrates to within 2e-5 of the CIE's 1 nm table's 106.857); zero
/// outside 380..780 nm and for NaN.
Xyz cie1931(double nm);
/// Chromaticity (x, y) of a colour; (0, 0) for black.
std::array<double, 2> chromaticity(const Xyz& c);
/// Linear sRGB of a CIE XYZ colour (IEC 61966-2-1 matrix; components may be
/// negative or above 1 for colours outside the sRGB gamut).
Rgb linear_srgb(const Xyz& c);
/// CIE XYZ of linear sRGB (the inverse, IEC 61966-2-1's forward matrix).
Xyz xyz(const Rgb& c);
/// Relative luminance of linear sRGB (the Y row of the inverse matrix).
double luminance(const Rgb& c);

/// The spectrum of the light.
enum class Illuminant {
  d65,        ///< CIE daylight, 6504 K (tabulated)
  equal,      ///< CIE illuminant E, equal energy per nanometre
  blackbody,  ///< Planck's law at a temperature (CIE illuminant A: 2856 K)
  led,        ///< a phosphor-converted white LED (model: see power())
};
struct LightSpectrum {
  Illuminant kind = Illuminant::d65;
  double kelvin = 6500;  ///< blackbody only
  bool operator==(const LightSpectrum&) const = default;
};

/// Relative spectral power of the light at `nm` (arbitrary scale; D65 is 0
/// outside its table's 380..780 nm, as the observer is). A blackbody takes
/// the temperatures wavelength_samples() accepts. The LED
/// is a model, not a CIE table: a blue InGaN peak (Gaussian, 450 nm, FWHM
/// 20 nm) plus the broad phosphor band (Gaussian, 560 nm, FWHM 120 nm) at
/// 0.6 of the blue peak's height: a cool white near 6000 K (x 0.320,
/// y 0.354), a little greener than the blackbody, as many real parts are.
double power(const LightSpectrum& light, double nm);
/// The light's own colour, integrated in 1 nm steps over 380..780 nm.
Xyz tristimulus(const LightSpectrum& light);

/// One wavelength of a spectral frame and the band of the spectrum it
/// stands for.
struct WavelengthSample {
  double nm = 0;            ///< where the index is evaluated: the band's centre
  double from_nm = 0, to_nm = 0;
  Rgb weight;               ///< linear sRGB added per unit irradiance
};

/// K samples splitting 380..780 nm into equal bands, weighted by the light
/// and the CIE observer and white-balanced: the weights sum to exactly
/// (1, 1, 1). Throws std::invalid_argument unless 1 <= k <= kMaxWavelengths.
std::vector<WavelengthSample> wavelength_samples(const LightSpectrum& light, int k);

}  // namespace caustic::optics
