// SPDX-License-Identifier: LGPL-2.1-or-later
// A scene's `water` section: the pool whose surface the wave solver moves
// (caustic/wave_solver.hpp) and the engine draws as a caustic face of shape
// "surface". It lives with the scene, which must read and check it without
// knowing the solver; the solver reads the same struct. docs/physics.md §14
// derives the stability bound; docs/scene-format.md lists the keys.
#pragma once

#include <cstdint>

namespace caustic::water {

struct WaveParams {
  int grid = 128;                ///< vertices per side, [16, 512]
  double size = 2.0;             ///< the pool's side, metres
  double wave_speed = 0.4;       ///< c, metres per second
  double damping = 0.3;          ///< gamma, 1/s: a wave's energy falls as exp(-gamma t)
  double time_step = 0;          ///< seconds, fixed, at most max_time_step(); 0: step_seconds() picks it
  double rain_rate = 0.0;        ///< drops per second over the whole pool (a Poisson process)
  double rain_strength = 0.002;  ///< depth of a rain drop's dent, metres (a visitor's drop, by default)
  double drop_radius = 0.03;     ///< a drop's radius (its Gaussian's sigma), metres
  double wind_height = 0;        ///< RMS height of the wind's waves, metres; 0: calm
  double wind_direction_deg = 0; ///< where the wind blows to, degrees from +x towards +y
  double wind_wavelength = 0.3;  ///< the wind waves' peak wavelength, metres
  std::uint64_t seed = 1;        ///< where and when rain falls, and the wind's waves
  double warmup_s = 0;           ///< seconds of rain simulated before the first frame, [0, 60]
  bool paused = false;           ///< a stream holds the water still (its clock stops) while set

  bool operator==(const WaveParams&) const = default;
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
/// The step the solver takes: time_step, or when that is 0 the largest
/// 1/(60 k) s within the bound, so that a 30 or 60 fps stream advances by
/// whole steps.
double step_seconds(const WaveParams& params);
/// Throws caustic::SceneError naming the key ("water.grid", "water.time_step",
/// ...) of the first value out of range; a time step above max_time_step()
/// is refused with the bound in the message.
void validate(const WaveParams& params);
/// Throws SceneError ("x", "y", "strength", "radius") for a drop outside
/// the pool, not finite, or with a radius under one grid spacing or over a
/// quarter pool; what WaveSolver::drop() checks first.
void check_drop(const WaveParams& params, double x, double y, double strength, double radius);

}  // namespace caustic::water
