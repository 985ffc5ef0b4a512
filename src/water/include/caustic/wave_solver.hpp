// SPDX-License-Identifier: LGPL-2.1-or-later
// A pool's water surface: the damped wave equation on a square height grid,
//   d2h/dt2 = c^2 lap(h) - gamma dh/dt,
// stepped at a fixed time step by the explicit centred (leapfrog) scheme
//   (1 + a) h[n+1] = 2 h[n] - (1 - a) h[n-1] + C^2 L h[n],
// with a = gamma dt / 2, C = c dt / dx the Courant number and L the
// five-point Laplacian times dx^2. The pool's walls reflect: the slope
// normal to a wall is zero (a mirrored ghost row), so the water's volume is
// kept exactly. Heights are metres about the still level; x and y run over
// [-size/2, size/2], row-major with y the slow index. docs/physics.md §14
// derives the stability bound and the oracles tests/water_test.cpp holds it to.
#pragma once

#include <cstdint>
#include <vector>

namespace caustic::water {

struct WaveParams {
  int grid = 128;                ///< vertices per side, [16, 512]
  double size = 2.0;             ///< the pool's side, metres
  double wave_speed = 0.4;       ///< c, metres per second
  double damping = 0.3;          ///< gamma, 1/s: a wave's energy falls as exp(-gamma t)
  double time_step = 1.0 / 60;   ///< seconds, fixed; at most max_time_step()
  double rain_rate = 0.0;        ///< drops per second over the whole pool (a Poisson process)
  double rain_strength = 0.002;  ///< depth of a rain drop's dent, metres
  double drop_radius = 0.03;     ///< a rain drop's radius (its Gaussian's sigma), metres
  std::uint64_t seed = 1;        ///< where and when rain falls
};

/// The Courant number the fixed step may reach. The scheme is stable for
/// C <= 1/sqrt(2) (von Neumann; at equality the checkerboard mode's double
/// root grows linearly), so the bound keeps 1% inside it.
inline constexpr double kMaxCourant = 0.7;

/// The row or column index `i` of a grid of `n` with the walls' ghosts
/// mirrored inside (-1 reads 1, n reads n - 2): the one rule behind the
/// solver's reflecting walls and the surface's slopes at them.
inline int mirrored(int i, int n) { return i < 0 ? -i : i >= n ? 2 * (n - 1) - i : i; }

/// The grid spacing, metres.
double spacing(const WaveParams& params);
/// The largest time step validate() accepts: kMaxCourant dx / c.
double max_time_step(const WaveParams& params);
/// Throws caustic::SceneError naming the key ("water.grid", "water.time_step",
/// ...) of the first value out of range; a time step above max_time_step()
/// is refused with the bound in the message.
void validate(const WaveParams& params);

class WaveSolver {
 public:
  /// Still water. Throws as validate() does.
  explicit WaveSolver(const WaveParams& params);

  /// A drop at (x, y) metres: a dent `strength` metres deep at its centre
  /// with a raised rim (the Laplacian of a Gaussian of sigma `radius`),
  /// less its mean so the water's volume is unchanged. Throws SceneError
  /// ("x", "y", "strength", "radius") for values outside the pool, not
  /// finite, or a radius under one grid spacing or over a quarter pool.
  void drop(double x, double y, double strength, double radius);
  /// One time step, rain included.
  void step();

  const WaveParams& params() const { return params_; }
  /// Heights of the newest step, grid x grid, metres.
  const std::vector<double>& heights() const { return now_; }
  std::uint64_t steps() const { return steps_; }
  double time() const { return static_cast<double>(steps_) * params_.time_step; }
  std::uint64_t raindrops() const { return raindrops_; }
  /// The scheme's discrete energy between the last two steps (per unit
  /// density and gravity-free: kinetic + c^2 times the product of the two
  /// steps' slopes), which it conserves exactly without damping.
  double energy() const;
  /// The water's volume above the still level (trapezoidal), m^3: zero for
  /// any sequence of drops.
  double volume() const;

 private:
  double weight(int i, int j) const;  // trapezoidal: 1/2 on walls, 1/4 in corners
  void rain();

  WaveParams params_;
  double courant2_, a_;
  std::vector<double> before_, now_, next_;
  std::uint64_t steps_ = 0, raindrops_ = 0;
  std::uint64_t rng_;
  double next_rain_ = 0;  // seconds
};

}  // namespace caustic::water
