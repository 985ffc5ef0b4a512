// SPDX-License-Identifier: LGPL-2.1-or-later
// The glow's size and blur, one definition for both post-processing paths
// (post_pass.cpp on the GL, cpu_post.cpp on the CPU), so that they draw one
// picture. The glow is computed on an image smaller by glow_shrink() per
// side: half, quarter or eighth as the radius grows, which keeps the
// Gaussian at least 2 texels wide for a smooth bilinear upsampling.
#pragma once

#include "caustic/receivers.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace caustic {

inline constexpr int kMaxBlurRadius = 48;     // blur.frag's kMaxRadius
inline constexpr std::size_t kMaxGlowCuts = 10;  // glow_cuts.glsl's kMaxCuts: 8 surfaces' tiles need 5 a side

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

/// Where the glow stops: the edges of the atlas's tiles across (x) and
/// down (y, GL's rows from the bottom) in glow texels, 0 and the glow's
/// size included. The atlas lays unrelated surfaces side by side, so a
/// surface's light glows over its own tile only: the blur and the tone
/// map's sampling of the glow treat each tile's edges as the image's. One
/// surface: {0, size}, the whole picture. Exact where the tiles' edges fall
/// on whole glow texels (picture sides that are multiples of 8); otherwise
/// the texel astride an edge mixes the two tiles' light.
struct GlowCuts {
  std::vector<int> x, y;
};

/// `tiles` as atlas_layout() gives them (from the top) for a picture
/// `height` pixels high whose glow is `glow_width` x `glow_height` texels.
inline GlowCuts glow_cuts(const std::vector<AtlasTile>& tiles, int height, int shrink, int glow_width,
                          int glow_height) {
  GlowCuts cuts{{0, glow_width}, {0, glow_height}};
  for (const AtlasTile& t : tiles) {
    for (const int x : {t.x, t.x + t.width}) cuts.x.push_back(std::clamp(x / shrink, 0, glow_width));
    for (const int y : {height - t.y - t.height, height - t.y}) cuts.y.push_back(std::clamp(y / shrink, 0, glow_height));
  }
  for (auto* c : {&cuts.x, &cuts.y}) {
    std::sort(c->begin(), c->end());
    c->erase(std::unique(c->begin(), c->end()), c->end());
  }
  return cuts;
}

/// The texels [lo, hi) between the two cuts around texel i (0 <= i < the last cut).
inline std::pair<int, int> glow_segment(const std::vector<int>& cuts, int i) {
  const auto after = std::upper_bound(cuts.begin(), cuts.end(), i);
  if (after == cuts.begin()) return {cuts.front(), cuts.size() > 1 ? cuts[1] : cuts.front()};
  if (after == cuts.end()) return {cuts[cuts.size() - 2], cuts.back()};
  return {*(after - 1), *after};
}

}  // namespace caustic
