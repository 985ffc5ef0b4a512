// SPDX-License-Identifier: LGPL-2.1-or-later
// Randomness a run repeats: splitmix64, whose sequence is fixed by its seed
// on every platform (the standard distributions are not), and the rain it
// schedules, shared by the wave solvers so that one seed rains alike on the
// CPU and on the GL. docs/physics.md §14.
#pragma once

#include "caustic/water_params.hpp"

#include <cmath>
#include <cstdint>

namespace caustic::water {

/// The next number of splitmix64 from `state`, uniform in [0, 1).
inline double uniform(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/// Rain on the pool: a Poisson process of rain_rate drops a second at
/// uniform places.
class Rain {
 public:
  /// Rain from `now` on, drawn from `state`; none while rain_rate is 0.
  Rain(const WaveParams& params, std::uint64_t state, double now)
      : rate_(params.rain_rate), half_(params.size / 2), state_(state) {
    if (rate_ > 0) next_ = now + wait();
  }

  /// Calls fall(x, y) (metres from the centre) for each drop due by `now`,
  /// in order; returns how many fell.
  template <typename Fall>
  int fall_until(double now, Fall&& fall) {
    int fallen = 0;
    if (rate_ <= 0) return fallen;
    while (next_ <= now) {
      const double x = (2 * uniform(state_) - 1) * half_;
      const double y = (2 * uniform(state_) - 1) * half_;
      fall(x, y);
      ++fallen;
      next_ += wait();
    }
    return fallen;
  }

 private:
  double wait() { return -std::log1p(-uniform(state_)) / rate_; }  // to the next drop, seconds

  double rate_, half_, next_ = 0;
  std::uint64_t state_;
};

}  // namespace caustic::water
