// SPDX-License-Identifier: LGPL-2.1-or-later
// Automatic exposure. The metering statistic is a quantile of the lit pixels'
// relative irradiance, taken from a histogram in log2 space so that the GPU
// (shaders/meter.comp) and the CPU (tests, calibration) bin alike: the same
// constants feed both. A quantile, not the mean or the maximum, because a
// caustic's focus can be 10^4 times its surroundings: metering on the peak
// would leave everything else black, metering on the mean clips the focus.
#pragma once

#include "caustic/image.hpp"
#include "caustic/scene.hpp"

#include <array>
#include <cstdint>

namespace caustic::exposure {

inline constexpr int kBins = 256;
inline constexpr float kLog2Lit = -12.0f;   ///< a pixel is lit above 2^-12 of the light's irradiance
inline constexpr float kBinsPerStop = 8.0f; ///< bins cover 2^-12 .. 2^20 in 1/8 stops (9%)
/// Metering reads every stride-th pixel across and down, so that at most
/// kMeterSide of them per side are binned: a 99th percentile needs no more,
/// and on a CPU renderer a full-size histogram cost half a frame.
inline constexpr int kMeterSide = 256;
inline int meter_stride(int width, int height) {
  const int side = width > height ? width : height;
  return side > kMeterSide ? (side + kMeterSide - 1) / kMeterSide : 1;
}
/// 8-bit level (of 1) the metered quantile lands on, after gamma: 0.92 is
/// 235 of 255. The curve 1 - exp(-x) reaches 255 only at 3x that value, so
/// at most (1 - quantile) of the lit pixels can clip, usually far fewer.
inline constexpr double kMeteredLevel = 0.92;

using Histogram = std::array<std::uint32_t, kBins>;

/// Counts one value into its bin when it is lit.
void count(Histogram& histogram, float value);

/// Histogram of the lit pixels of `image` that the meter reads (every
/// meter_stride-th across and down, from the bottom row: GL's first).
Histogram histogram(const HdrImage& image);

/// The value below which fraction `q` of the lit pixels lie, interpolated
/// geometrically within its bin; 0 when nothing is lit.
double quantile(const Histogram& histogram, double q);

/// The exposure that maps `value` to kMeteredLevel through
/// (1 - exp(-exposure value))^(1/gamma); 1 when value is 0.
double exposure_for(double value, double gamma);

/// One step of the shown exposure towards `target` after `dt` seconds, with
/// time constant `tau` (in log space: brightening and darkening alike). It
/// lands on the target once within 1%, so a still picture settles.
double adapt(double shown, double target, double dt, double tau);

/// The exposure the engine settles on for `image` with the global operator:
/// metered and compensated ("auto") or as written ("manual"). Comparisons of
/// tone-mapped pictures use it so that they judge what a viewer sees.
double settled_exposure(const PostParams& post, const HdrImage& image);

}  // namespace caustic::exposure
