// SPDX-License-Identifier: LGPL-2.1-or-later
// What the wave solvers' tests measure a surface by, for either solver: a
// drop's radial profile and the radius its trough has travelled to.
#pragma once

#include "caustic/water_params.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <vector>

namespace caustic::water::testing {

// The azimuthal mean of the heights in rings `bin` wide about the centre:
// the profile of a centred drop.
inline std::vector<double> radial_profile(const WaveParams& p, const std::vector<double>& heights, double bin) {
  const int n = p.grid;
  const double dx = spacing(p), half = p.size / 2;
  std::vector<double> sum(static_cast<std::size_t>(half / bin) + 1, 0.0), count(sum.size(), 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r = std::hypot(-half + i * dx, -half + j * dx);
      const auto b = static_cast<std::size_t>(r / bin);
      if (b >= sum.size()) continue;
      sum[b] += heights[static_cast<std::size_t>(j) * n + i];
      count[b] += 1;
    }
  for (std::size_t b = 0; b < sum.size(); ++b) sum[b] = count[b] > 0 ? sum[b] / count[b] : 0.0;
  return sum;
}

// Radius of the deepest trough beyond `from`, refined by a parabola through
// its bin and the two beside it. A drop's dent travels out as this trough.
inline double trough_radius(const std::vector<double>& profile, double bin, double from) {
  std::size_t best = static_cast<std::size_t>(from / bin);
  for (std::size_t b = best; b + 1 < profile.size(); ++b)
    if (profile[b] < profile[best]) best = b;
  const double l = profile[best - 1], m = profile[best], r = profile[best + 1];
  const double offset = 0.5 * (l - r) / (l - 2 * m + r);
  return (static_cast<double>(best) + 0.5 + offset) * bin;
}

// A pool 4 m wide whose ring stays clear of the walls for 3 s at c = 0.5,
// Courant number 0.5, no damping.
inline WaveParams ring_pool() {
  WaveParams p;
  p.grid = 257;
  p.size = 4.0;
  p.wave_speed = 0.5;
  p.damping = 0.0;
  p.time_step = 0.5 * spacing(p) / p.wave_speed;
  return p;
}

/// Where a centred drop's trough has travelled at 1.2, 2.1 and 3 s
/// (before it reaches the walls of ring_pool()).
struct Ring {
  std::vector<double> t, r;
  double speed() const { return (r[2] - r[0]) / (t[2] - t[0]); }
  /// The first half's speed less the second's: zero for a steady ring.
  double unsteadiness() const { return (r[1] - r[0]) / (t[1] - t[0]) - (r[2] - r[1]) / (t[2] - t[1]); }
};

/// Drops a 1 mm dent three spacings wide in the middle of `s`, a solver on
/// ring_pool(), and follows its ring.
template <typename Solver>
Ring follow_ring(Solver& s) {
  const WaveParams& p = s.params();
  s.drop(0, 0, 1e-3, 3 * spacing(p));
  const double bin = spacing(p) / 2;
  Ring ring;
  for (double at : {1.2, 2.1, 3.0}) {
    while (s.time() < at - 1e-9) s.step();
    ring.t.push_back(s.time());
    ring.r.push_back(trough_radius(radial_profile(p, s.heights(), bin), bin, 0.5 * p.wave_speed * s.time()));
  }
  std::printf("ring trough at %.4f, %.4f, %.4f m: %.4f m/s against c = %.4f\n", ring.r[0], ring.r[1], ring.r[2],
              ring.speed(), p.wave_speed);
  return ring;
}

/// Drops scattered off centre, one by a corner.
template <typename Solver>
void scatter_drops(Solver& s) {
  const double r = 3 * spacing(s.params()), half = s.params().size / 2;
  s.drop(0.1 * half, -0.2 * half, 2e-3, r);
  s.drop(-0.6 * half, 0.5 * half, -1e-3, r);
  s.drop(0.95 * half, 0.9 * half, 1.5e-3, 2 * r);
}

}  // namespace caustic::water::testing
