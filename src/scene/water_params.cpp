// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/water_params.hpp"

#include "caustic/scene.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace caustic::water {
namespace {

// Rain is this many drops a second at most: a step then meets a few, not a
// loop without end.
constexpr double kMaxRainRate = 200.0;
// Warming up is simulated before the first frame, on the thread that loads
// the scene; a minute at most, and at most kMaxWarmupUpdates of work.
constexpr double kMaxWarmup = 60.0;
// What the solver may be asked, in cell updates (grid² a step), whatever
// the step: a simulated second, which a stream owes every second of its
// life (a frame at most Pool::kMaxAdvance of it), and the warm-up, which
// holds the thread that loads the scene. A cell update cost 7-13 ns on the
// 2-core machine of docs/performance.md: 2^26 a second is the finest grid
// at the step its default waves need (512², 1/180 s: 4.7e7) with room to
// spare, 2^29 about five seconds of warm-up. A 10 us step on that grid
// once asked 85 s of work for each frame a stream drew.
constexpr double kMaxUpdatesPerSecond = double(1 << 26);
constexpr double kMaxWarmupUpdates = double(1 << 29);

std::string text(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

void require(bool ok, const char* key, const std::string& what) {
  if (!ok) throw SceneError(key, what);
}

}  // namespace

double spacing(const WaveParams& p) { return p.size / (p.grid - 1); }

double max_time_step(const WaveParams& p) { return kMaxCourant * spacing(p) / p.wave_speed; }

double step_seconds(const WaveParams& p) {
  if (p.time_step > 0) return p.time_step;
  return 1.0 / (60.0 * std::ceil(1.0 / (60.0 * max_time_step(p))));
}

void validate(const WaveParams& p) {
  require(p.grid >= 16 && p.grid <= 512, "water.grid", "must be 16 to 512 vertices a side");
  require(std::isfinite(p.size) && p.size >= 0.05 && p.size <= 100, "water.size", "must be 0.05 to 100 m");
  require(std::isfinite(p.wave_speed) && p.wave_speed > 0 && p.wave_speed <= 100, "water.wave_speed",
          "must be above 0 and at most 100 m/s");
  require(std::isfinite(p.damping) && p.damping >= 0 && p.damping <= 100, "water.damping",
          "must be 0 to 100 per second");
  require(std::isfinite(p.time_step) && p.time_step >= 0, "water.time_step",
          "must be a positive number of seconds, or 0 to let the bound choose");
  require(p.time_step <= max_time_step(p), "water.time_step",
          "must be at most " + text(max_time_step(p)) + " s for this grid and wave speed (Courant number " +
              text(kMaxCourant) + "); the scheme is unstable beyond it");
  // Steps so short that a frame would need more than a thousand of them.
  require(step_seconds(p) >= 1e-5, "water.time_step",
          "the stability bound asks for steps under 10 us: make the grid coarser or the waves slower");
  require(std::isfinite(p.rain_rate) && p.rain_rate >= 0 && p.rain_rate <= kMaxRainRate, "water.rain_rate",
          "must be 0 to " + text(kMaxRainRate) + " drops per second");
  require(std::isfinite(p.rain_strength) && std::abs(p.rain_strength) <= 0.05 * p.size, "water.rain_strength",
          "must be at most 5% of the pool's size in magnitude");
  // Only rain uses it: a grid too coarse for the default drop matters only when it rains.
  require(std::isfinite(p.drop_radius) && p.drop_radius <= p.size / 4 &&
              (p.rain_rate == 0 || p.drop_radius >= spacing(p)),
          "water.drop_radius",
          "must be at most a quarter of the pool and, when it rains, at least one grid spacing (" +
              text(spacing(p)) + " m)");
  require(std::isfinite(p.wind_height) && p.wind_height >= 0 && p.wind_height <= 0.02 * p.size, "water.wind_height",
          "must be 0 to 2% of the pool's size");
  require(p.wind_height == 0 || p.damping > 0, "water.wind_height",
          "wind drives the water at the damping's rate: give water.damping a value above 0");
  require(std::isfinite(p.wind_direction_deg) && std::abs(p.wind_direction_deg) <= 360, "water.wind_direction_deg",
          "must be -360 to 360 degrees");
  // An octave shorter than the peak must still span four grid spacings
  // (a grid too coarse for the default matters only when the wind blows).
  require(std::isfinite(p.wind_wavelength) && p.wind_wavelength > 0 && p.wind_wavelength <= p.size &&
              (p.wind_height == 0 || p.wind_wavelength >= 8 * spacing(p)),
          "water.wind_wavelength",
          "must be at most the pool's size and, when the wind blows, at least eight grid spacings (" +
              text(8 * spacing(p)) + " m)");
  require(std::isfinite(p.warmup_s) && p.warmup_s >= 0 && p.warmup_s <= kMaxWarmup, "water.warmup_s",
          "must be 0 to " + text(kMaxWarmup) + " seconds");
  const double per_second = double(p.grid) * p.grid / step_seconds(p);
  // Without a step of its own, the step is the wave speed's: named by that,
  // which a session may change (its grid is fixed).
  require(per_second <= kMaxUpdatesPerSecond, p.time_step > 0 ? "water.time_step" : "water.wave_speed",
          "a second of this water is " + text(per_second) + " cell updates (grid² / step), more than " +
              text(kMaxUpdatesPerSecond) + ": " +
              (p.time_step > 0 ? "lengthen the step or coarsen the grid (water.grid)"
                               : "slow the waves or coarsen the grid (water.grid)"));
  require(p.warmup_s * per_second <= kMaxWarmupUpdates, "water.warmup_s",
          "must be at most " + text(kMaxWarmupUpdates / per_second) + " s for this grid and step (" +
              text(per_second) + " cell updates a second, " + text(kMaxWarmupUpdates) +
              " at most before the first frame)");
}

void check_drop(const WaveParams& p, double x, double y, double strength, double radius) {
  const double half = p.size / 2;
  require(std::isfinite(x) && std::abs(x) <= half, "x", "must lie in the pool, within " + text(half) + " m of its centre");
  require(std::isfinite(y) && std::abs(y) <= half, "y", "must lie in the pool, within " + text(half) + " m of its centre");
  require(std::isfinite(strength) && std::abs(strength) <= 0.05 * p.size, "strength",
          "must be at most 5% of the pool's size in magnitude");
  require(std::isfinite(radius) && radius >= spacing(p) && radius <= p.size / 4, "radius",
          "must be from one grid spacing (" + text(spacing(p)) + " m) to a quarter of the pool");
}

}  // namespace caustic::water
