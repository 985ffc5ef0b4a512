// SPDX-License-Identifier: LGPL-2.1-or-later
// Wind (docs/physics.md §14): the forced scheme follows waves that solve the
// unforced one exactly, so a standing wave the walls allow is reached from
// still water to rounding; the wind's spectrum has the RMS height, the
// directions and the wavenumbers asked for, from its seed; a windy pool's
// waves are of the wind's height; wind without damping is refused.
#include "caustic/scene.hpp"
#include "caustic/wave_solver.hpp"
#include "refusal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace caustic::water {
namespace {

constexpr double kPi = std::numbers::pi;

WaveParams breezy() {
  WaveParams p;
  p.grid = 64;
  p.damping = 1.0;
  return p;
}

}  // namespace

// cos(kx x) cos(ky y) cos(omega t) with kx size / 2 and ky size / 2 whole
// multiples of pi has no slope across the walls: the sum of four waves
// (+-kx, +-ky) that the pool can hold exactly. From still water the error
// decays as exp(-gamma t / 2): after 30 s at gamma = 1, by e^-15.
TEST(Wind, TheForcedWaterReachesAStandingWaveTheWallsAllow) {
  const WaveParams p = breezy();
  WaveSolver solver(p);
  const double kx = 3 * kPi, ky = 2 * kPi, amplitude = 0.0005;
  const double omega = scheme_omega(p, solver.time_step(), kx, ky);
  std::vector<Wave> waves;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) waves.push_back({sx * kx, sy * ky, amplitude, 0.0, omega});
  solver.set_waves(waves);
  const int steps = static_cast<int>(std::lround(30.0 / solver.time_step()));
  for (int s = 0; s < steps; ++s) solver.step();
  const int n = p.grid;
  double worst = 0, peak = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double target = solver.forcing()->target(solver.time(), i, j);
      worst = std::max(worst, std::abs(solver.heights()[static_cast<std::size_t>(j) * n + i] - target));
      peak = std::max(peak, std::abs(target));
    }
  std::printf("standing wave of 4 x %.1f mm after 30 s: worst departure %.2e m (peak now %.2e m)\n", 1e3 * amplitude,
              worst, peak);
  EXPECT_LT(worst, 1e-5 * 4 * amplitude);
  EXPECT_GT(peak, 0.5 * 4 * amplitude * std::abs(std::cos(omega * solver.time())));
}

TEST(Wind, TheSpectrumHasTheHeightDirectionsAndWavenumbersAskedFor) {
  WaveParams p = breezy();
  p.wind_height = 0.003;
  p.wind_direction_deg = 30;
  p.wind_wavelength = 0.4;
  const double dt = step_seconds(p);
  const auto waves = wind_waves(p, dt);
  ASSERT_EQ(waves.size(), static_cast<std::size_t>(kWindWaves));
  const double kp = 2 * kPi / p.wind_wavelength, c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  double power = 0, along = 0;
  for (const Wave& w : waves) {
    const double k = std::hypot(w.kx, w.ky);
    EXPECT_GE(k, kp / 2 * (1 - 1e-12));
    EXPECT_LE(k, 2 * kp * (1 + 1e-12));
    EXPECT_GT(w.kx * c + w.ky * s, 0.0) << "a wave against the wind";
    EXPECT_DOUBLE_EQ(w.omega, scheme_omega(p, dt, w.kx, w.ky));
    power += w.amplitude * w.amplitude / 2;
    along += w.amplitude * w.amplitude * (w.kx * c + w.ky * s) / k;
  }
  EXPECT_NEAR(std::sqrt(power), p.wind_height, 1e-12);
  // cos^2 spread: the power-weighted mean of cos(angle to the wind) is 8 / (3 pi) = 0.85 in the limit.
  EXPECT_GT(along / (2 * power), 0.6);
  // One seed, one sea; another seed, another.
  const auto again = wind_waves(p, dt);
  EXPECT_EQ(again.front().phase, waves.front().phase);
  p.seed = 2;
  EXPECT_NE(wind_waves(p, dt).front().phase, waves.front().phase);
  p.wind_height = 0;
  EXPECT_TRUE(wind_waves(p, dt).empty());
}

TEST(Wind, AWindyPoolsWavesHaveTheWindsHeight) {
  WaveParams p = breezy();
  p.grid = 128;
  p.wind_height = 0.002;
  WaveSolver solver(p);
  for (int s = 0; s < static_cast<int>(12.0 / solver.time_step()); ++s) solver.step();
  // The middle half of the pool, away from what the walls reflect.
  const int n = p.grid;
  double sum = 0, target = 0;
  int count = 0;
  for (int j = n / 4; j < 3 * n / 4; ++j)
    for (int i = n / 4; i < 3 * n / 4; ++i, ++count) {
      const double h = solver.heights()[static_cast<std::size_t>(j) * n + i];
      sum += h * h;
      const double t = solver.forcing()->target(solver.time(), i, j);
      target += t * t;
    }
  const double rms = std::sqrt(sum / count), wanted = std::sqrt(target / count);
  std::printf("windy pool after 12 s: RMS height %.2f mm in the middle (the wind's waves there: %.2f mm; asked %.2f)\n",
              1e3 * rms, 1e3 * wanted, 1e3 * p.wind_height);
  EXPECT_GT(rms, 0.5 * p.wind_height);
  EXPECT_LT(rms, 2.0 * p.wind_height);
  EXPECT_NEAR(solver.volume(), 0.0, 1e-3 * p.wind_height * p.size * p.size);
}

TEST(Wind, WindWithoutDampingOrResolutionIsRefused) {
  const auto key_of = [](WaveParams p) { return caustic::testing::refused_key<SceneError>([&] { validate(p); }); };
  WaveParams calm = breezy();
  calm.wind_height = 0.001;
  calm.damping = 0;
  EXPECT_EQ(key_of(calm), "water.wind_height");
  WaveParams fine = breezy();
  fine.wind_height = 0.001;
  fine.wind_wavelength = 7 * spacing(fine);
  EXPECT_EQ(key_of(fine), "water.wind_wavelength");
  fine.wind_wavelength = 8 * spacing(fine);
  EXPECT_EQ(key_of(fine), "accepted");
  WaveParams high = breezy();
  high.wind_height = 0.05;
  EXPECT_EQ(key_of(high), "water.wind_height");
}

}  // namespace caustic::water
