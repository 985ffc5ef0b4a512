// SPDX-License-Identifier: LGPL-2.1-or-later
// The glow's size and blur, one definition for both post-processing paths
// (post_pass.cpp on the GL, cpu_post.cpp on the CPU), so that they draw one
// picture. The glow is computed on an image smaller by glow_shrink() per
// side: half, quarter or eighth as the radius grows, which keeps the
// Gaussian at least 2 texels wide for a smooth bilinear upsampling.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace caustic {

inline constexpr int kMaxBlurRadius = 48;  // blur.frag's kMaxRadius

inline int glow_shrink(double bloom_radius) { return bloom_radius < 8 ? 2 : bloom_radius < 16 ? 4 : 8; }

/// Tap k's weight (k = 0 .. radius, used at ±k) of the normalised Gaussian
/// of sigma bloom_radius / shrink small texels, cut at 3 sigma.
inline std::vector<double> glow_weights(double bloom_radius, int shrink) {
  const double sigma = bloom_radius / shrink;
  const int radius = std::clamp(static_cast<int>(std::ceil(3.0 * sigma)), 1, kMaxBlurRadius);
  std::vector<double> weights(radius + 1);
  double total = 0;
  for (int k = 0; k <= radius; ++k) {
    weights[k] = std::exp(-0.5 * k * k / (sigma * sigma));
    total += k == 0 ? weights[k] : 2 * weights[k];
  }
  for (double& w : weights) w /= total;
  return weights;
}

}  // namespace caustic
