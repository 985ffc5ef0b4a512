// SPDX-License-Identifier: LGPL-2.1-or-later
// Wind on the pool: travelling waves drawn from a Phillips-like spectrum,
// and the force that makes the water follow them. With h* a sum of waves
// that solves the undamped scheme exactly (each travels at the scheme's own
// frequency for its wavenumber), the damped scheme driven by f = γ ∂h*/∂t
// (its centred difference) is solved exactly by h = h*: from still water the
// surface converges to the wind's waves at the damping's rate, away from the
// walls, which reflect what reaches them. docs/physics.md §14.
#pragma once

#include "caustic/water_params.hpp"

#include <complex>
#include <vector>

namespace caustic::water {

/// h = amplitude cos(kx x + ky y - omega t + phase), metres, 1/m, rad/s.
struct Wave {
  double kx = 0, ky = 0, amplitude = 0, phase = 0, omega = 0;
};

/// Travelling waves the wind raises.
inline constexpr int kWindWaves = 32;

/// The scheme's angular frequency for the wavenumber (kx, ky):
/// sin(omega dt / 2) = (c dt / dx) |(sin(kx dx / 2), sin(ky dx / 2))|.
double scheme_omega(const WaveParams& params, double dt, double kx, double ky);

/// kWindWaves waves from the seed: wavenumbers log-uniform an octave either
/// side of 2 pi / wind_wavelength, weighted by the Phillips-like density
/// exp(-(kp/k)^2) (kp/k)^2 per log k, directions spread as cos^2 about the
/// wind's (never against it), random phases, amplitudes scaled so that the
/// sum's RMS height is wind_height. Empty when wind_height is 0.
std::vector<Wave> wind_waves(const WaveParams& params, double dt);

/// f(x, t) = γ (h*(t + dt) - h*(t - dt)) / (2 dt) on the grid, evaluated
/// separably: a complex factor per row and per column and wave.
class Forcing {
 public:
  Forcing(const WaveParams& params, double dt, std::vector<Wave> waves);
  /// out[j * grid + i] = dt^2 f(x_i, y_j, t).
  void evaluate(double t, std::vector<double>& out) const;
  /// h*(x_i, y_j, t) (tests).
  double target(double t, int i, int j) const;
  const std::vector<Wave>& waves() const { return waves_; }

 private:
  int n_;
  double dt_, gamma_;
  std::vector<Wave> waves_;
  std::vector<std::complex<double>> rows_, columns_;  // [i * W + w], [j * W + w]: exp(i k x)
  std::vector<double> rows_re_, rows_im_;  // rows_ by wave, [w * n + i]: a wave's whole row at a time
};

}  // namespace caustic::water
