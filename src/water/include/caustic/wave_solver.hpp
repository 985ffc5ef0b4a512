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

#include "caustic/rain.hpp"
#include "caustic/water_params.hpp"
#include "caustic/wind.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace caustic::water {

/// A grid point's trapezoidal weight: 1/2 on a wall, 1/4 in a corner.
inline double trapezoid_weight(int i, int j, int n) {
  return (i == 0 || i == n - 1 ? 0.5 : 1.0) * (j == 0 || j == n - 1 ? 0.5 : 1.0);
}

/// The scheme's discrete energy between two successive steps' heights
/// (WaveSolver::energy()), for any solver's heights.
double scheme_energy(const WaveParams& params, double dt, const std::vector<double>& before,
                     const std::vector<double>& now);
/// The trapezoidal volume of a grid of heights, m^3 (WaveSolver::volume()).
double trapezoidal_volume(const WaveParams& params, const std::vector<double>& heights);

/// What a step depends on besides the parameters and the wind: the state
/// another solver (the GL's, caustic/wave_gl.hpp) takes over and hands back.
struct WaveState {
  std::vector<double> before, now;  ///< the last two steps' heights
  std::uint64_t steps = 0, raindrops = 0;
  double time = 0;
  Rain rain;  ///< the rain's schedule from `time` on
};

class WaveSolver {
 public:
  /// Still water. Throws as validate() does.
  explicit WaveSolver(const WaveParams& params);

  /// A drop at (x, y) metres: a dent `strength` metres deep at its centre
  /// with a raised rim (the Laplacian of a Gaussian of sigma `radius`),
  /// less its mean so the water's volume is unchanged. Throws as
  /// check_drop() does.
  void drop(double x, double y, double strength, double radius);
  /// One time step, rain and wind included.
  void step();
  /// Drives the water towards these travelling waves instead of the
  /// wind's (their omega is taken as given); empty: no forcing. Needs
  /// damping above 0 to have an effect. Kept until retune() changes a
  /// wind key, the seed, the wave speed or the step.
  void set_waves(std::vector<Wave> waves);
  /// The waves the water is driven towards (empty without wind).
  const Forcing* forcing() const { return forcing_ ? &*forcing_ : nullptr; }
  /// Takes new values for what may change while the water moves (wave
  /// speed, damping, time step, rain, seed, pause); the heights stay, and a
  /// new time step keeps the surface's velocity. Throws SceneError as
  /// validate() does, or naming "water.grid" or "water.size" when those
  /// differ, and then changes nothing.
  void retune(const WaveParams& params);

  const WaveParams& params() const { return params_; }
  /// The state to go on from elsewhere.
  WaveState state() const { return {before_, now_, steps_, raindrops_, time_, rain_}; }
  /// Goes on from `state` (another solver's with these parameters and the
  /// wind's waves): the same steps follow as if this solver had taken
  /// them. Throws std::invalid_argument when its heights are not grid x grid.
  void restore(WaveState state);
  /// Heights of the newest step, grid x grid, metres.
  const std::vector<double>& heights() const { return now_; }
  std::uint64_t steps() const { return steps_; }
  /// The step taken (step_seconds()), seconds.
  double time_step() const { return dt_; }
  /// Seconds simulated.
  double time() const { return time_; }
  std::uint64_t raindrops() const { return raindrops_; }
  /// The scheme's discrete energy between the last two steps (per unit
  /// density and gravity-free: kinetic + c^2 times the product of the two
  /// steps' slopes), which it conserves exactly without damping.
  double energy() const;
  /// The water's volume above the still level (trapezoidal), m^3: zero for
  /// any sequence of drops.
  double volume() const;

 private:
  void rain();

  WaveParams params_;
  void derive();  // dt_, courant2_, a_ from params_

  double dt_ = 0, courant2_ = 0, a_ = 0, time_ = 0;
  std::vector<double> before_, now_, next_;
  std::uint64_t steps_ = 0, raindrops_ = 0;
  Rain rain_;
  std::optional<Forcing> forcing_;
  std::vector<double> force_;  // dt^2 f of the current step
};

}  // namespace caustic::water
