// SPDX-License-Identifier: LGPL-2.1-or-later
// The CIE tables behind colour.hpp, sampled every kStepNm from kFirstNm.
// Kept apart so that the 160 lines of numbers sit in one file with their
// source, and colour.cpp reads as the method that uses them.
#pragma once

#include <array>

namespace caustic::optics::cie {

inline constexpr double kFirstNm = 380, kStepNm = 5;
inline constexpr int kSamples = 81;  // 380..780 nm

struct Cmf {
  double x, y, z;
};

/// CIE 1931 2-degree colour-matching functions x-bar, y-bar, z-bar.
extern const std::array<Cmf, kSamples> kObserver1931;
/// CIE standard illuminant D65, relative spectral power (560 nm: 100).
extern const std::array<double, kSamples> kD65;

}  // namespace caustic::optics::cie
