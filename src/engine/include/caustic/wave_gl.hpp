// SPDX-License-Identifier: LGPL-2.1-or-later
// The pool's wave solver stepped by the GL: the scheme, walls, drops, rain
// and wind of wave_solver.hpp, in 32-bit floats in shader storage buffers,
// so that a GPU advances the water without the heights crossing the bus.
// The CPU keeps what is per drop or per step rather than per point: the
// rain's schedule (the same seed rains alike on both solvers), a drop's
// volume remainder, and the wind's per-wave phases and trapezoidal mean (a
// sum of separable waves, summed once per wave). Floats round to about
// 1e-7 of the heights a step, so the two solvers agree to rounding, not to
// the bit; each repeats itself bit for bit on one machine.
// Every call needs the same current GL 4.5 context (compute shaders).
#pragma once

#include "caustic/pool.hpp"
#include "caustic/wave_solver.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace caustic::water {

class WaveSolverGl : public Stepper {
 public:
  /// Still water. Throws SceneError as validate() does, EngineError when the
  /// GL cannot build the solver.
  explicit WaveSolverGl(const WaveParams& params);
  /// Water that goes on from `state` (a WaveSolver's with these parameters
  /// and the wind's waves). Throws as above, or std::invalid_argument when
  /// the state's heights are not grid x grid.
  WaveSolverGl(const WaveParams& params, const WaveState& state);
  ~WaveSolverGl() override;
  WaveSolverGl(const WaveSolverGl&) = delete;
  WaveSolverGl& operator=(const WaveSolverGl&) = delete;

  /// As WaveSolver::drop (throws as check_drop() does).
  void drop(double x, double y, double strength, double radius) override;
  /// One time step, rain and wind included.
  void step() override;
  /// The last two steps' heights read back, with the counts and the rain.
  WaveState state() const override;

  const WaveParams& params() const;
  double time_step() const;
  double time() const;
  std::uint64_t steps() const;
  std::uint64_t raindrops() const;
  /// Waits until the GL has taken every step asked for (benchmarks).
  void finish() const;
  /// The newest step's heights, read back (grid x grid, metres, row-major).
  std::vector<double> heights() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace caustic::water
