// SPDX-License-Identifier: LGPL-2.1-or-later
// The plano-convex lens's exact rotationally symmetric ray map (the
// physics notes, ch. 7), traced in 2D with scalar trigonometry so that it
// shares nothing with the renderers it judges.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

namespace caustic::oracle {

inline constexpr double kRadius = 40.0;  // radius of curvature
inline constexpr double kIor = 1.5;
inline constexpr double kFocal = kRadius / (kIor - 1.0);

// Screen radius of the ray that enters the flat face at radius r (parallel
// light along -z, flat face up, apex at z = 0), screen at z = -distance.
inline double ray_map(double r, double distance) {
  const double root = std::sqrt(kRadius * kRadius - r * r);
  const double surface_z = kRadius - root;
  // Outward normal (r, -root) / R; inside, the ray travels along -z.
  const double sin_i = r / kRadius;                 // angle between ray and normal
  const double sin_t = kIor * sin_i;                // leaving glass
  const double deviation = std::asin(sin_t) - std::asin(sin_i);  // toward the axis
  return r - (surface_z + distance) * std::tan(deviation);
}

// Radius where the ray map folds over (d rs / d r = 0): the focus ring.
// Before it the map increases; after it, decreases. r_max if it never folds.
inline double fold_radius(double distance, double r_max) {
  const double h = 1e-6;
  auto slope = [&](double r) { return (ray_map(r + h, distance) - ray_map(r - h, distance)) / (2 * h); };
  if (slope(r_max) > 0) return r_max;
  double lo = 0.0, hi = r_max;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slope(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The preimage radius of screen radius rs on the monotone branch [a, b]
// (increasing or decreasing), or a negative value when rs is not reached.
inline double preimage(double rs, double distance, double a, double b) {
  const double fa = ray_map(a, distance), fb = ray_map(b, distance);
  if ((rs - fa) * (rs - fb) > 0) return -1;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (a + b);
    ((ray_map(mid, distance) - rs) * (fa - rs) > 0 ? a : b) = mid;
  }
  return 0.5 * (a + b);
}

/// A square screen that holds the whole bright disk at `distance`.
inline double lens_screen_size(double distance, double half_aperture) {
  const double corner = half_aperture * std::sqrt(2.0);
  return 2.0 * ray_map(fold_radius(distance, corner), distance) + 1.0;
}

/// Relative L1 of a square render (screen of side `screen_size` centred on
/// the axis) against E(rs) = sum over branches of r / (rs |d rs / d r|) for
/// a lens of square aperture +-half. Pixels within 4 pixels of a caustic
/// (the focus ring) or of the aperture edge's image, and the axis itself,
/// are left out: there a pixel's mean and the value at its centre differ.
template <typename Image>
std::pair<double, int> compare_with_ray_map(const Image& img, double screen_size, double z, double half) {
  const double corner = half * std::sqrt(2.0);
  const double r_fold = fold_radius(z, corner);
  const double rs_max = ray_map(r_fold, z);
  const double pixel = screen_size / img.width;
  double diff = 0, sum = 0;
  int used = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double px = (x + 0.5) * pixel - 0.5 * screen_size, py = 0.5 * screen_size - (y + 0.5) * pixel;
      const double rs = std::hypot(px, py);
      if (rs < 2 * pixel || rs > rs_max - 4 * pixel) continue;
      const double r_edge = half / std::max(std::abs(px / rs), std::abs(py / rs));  // aperture edge
      double e = 0;
      bool near_edge = false;
      for (const auto& [a, b] : {std::pair{0.0, r_fold}, std::pair{r_fold, corner}}) {
        const double r = preimage(rs, z, a, b);
        if (r < 0 || r > r_edge) continue;
        const double h = 1e-6;
        const double slope = (ray_map(r + h, z) - ray_map(r - h, z)) / (2 * h);
        if (std::abs(ray_map(r_edge, z) - rs) < 4 * pixel) near_edge = true;
        e += r / (rs * std::abs(slope));
      }
      if (near_edge || std::abs(ray_map(std::min(r_edge, r_fold), z) - rs) < 4 * pixel) continue;
      diff += std::abs(img.at(x, y) - e);
      sum += e;
      ++used;
    }
  return {diff / sum, used};
}

}  // namespace caustic::oracle
