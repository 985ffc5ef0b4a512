// SPDX-License-Identifier: LGPL-2.1-or-later
// How far a rendered irradiance image is from a reference: the measures the
// accuracy work quotes (docs/accuracy.md), in one place.
#pragma once

#include "caustic/image.hpp"

namespace caustic {

/// Box-filters an image by an integer factor in both directions, keeping the
/// mean. Errors are compared after this, where the reference's photon noise
/// is small next to the differences between methods. Throws
/// std::invalid_argument when the factor does not divide both sides.
HdrImage box_down(const HdrImage& image, int factor);

struct ImageError {
  double relative_l1 = 0;    ///< sum |a - r| / sum |r|
  double relative_rmse = 0;  ///< RMSE divided by the reference's mean
  double ssim = 1;           ///< of the tone-mapped images, see tonemapped_ssim
};

/// Compares `image` with `reference` (same size). Throws
/// std::invalid_argument on a size mismatch or an all-black reference.
ImageError compare(const HdrImage& image, const HdrImage& reference, double exposure = 1.0, double gamma = 2.2);

/// Mean SSIM (Wang, Bovik, Sheikh, Simoncelli 2004: 8x8 windows, stride 4,
/// K1 = 0.01, K2 = 0.03, dynamic range 1) of the two images after the
/// display tone map 1 - exp(-exposure E), then gamma: the same curve as
/// shaders/tonemap.frag without bloom, so it judges what a viewer sees.
double tonemapped_ssim(const HdrImage& a, const HdrImage& b, double exposure, double gamma);

}  // namespace caustic
