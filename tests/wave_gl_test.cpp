// SPDX-License-Identifier: LGPL-2.1-or-later
// The GL's wave solver (wave_gl.hpp) against the wave equation's laws, as
// water_test.cpp holds the CPU's (docs/physics.md §14): a ring's speed, the
// damping's decay rate, the scheme's energy to float rounding, no growth at
// the largest step, the kept volume; then against the CPU solver with rain,
// wind and drops, and against itself run twice; then taking the CPU's state
// over and handing it back, alone and stepping a pool.
#include "caustic/wave_gl.hpp"
#include "gl_test_support.hpp"
#include "water_test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace caustic::water {
namespace {

using caustic::testing::GlTest;
using namespace caustic::water::testing;
using WaveGl = GlTest;

double peak(const std::vector<double>& heights) {
  double top = 0;
  for (double h : heights) top = std::max(top, std::abs(h));
  return top;
}

TEST_F(WaveGl, ADropsRingSpreadsAtTheWaveSpeed) {
  WaveSolverGl s(ring_pool());
  const Ring ring = follow_ring(s);
  EXPECT_NEAR(ring.speed(), s.params().wave_speed, 0.02 * s.params().wave_speed);
  EXPECT_NEAR(ring.unsteadiness(), 0.0, 0.02 * s.params().wave_speed);
}

TEST_F(WaveGl, EnergyDecaysAtTheSetDampingAndIsKeptWithoutIt) {
  for (double gamma : {0.5, 0.0}) {
    WaveParams p;
    p.damping = gamma;
    p.time_step = max_time_step(p);
    WaveSolverGl s(p);
    scatter_drops(s);
    s.step();
    auto before = s.heights();
    double st = 0, sl = 0, stt = 0, stl = 0, count = 0, start = 0, drift = 0, volume = 0;
    while (s.time() < 6.0) {
      s.step();
      auto now = s.heights();
      const double e = scheme_energy(p, s.time_step(), before, now);
      if (start == 0) start = e;
      drift = std::max(drift, std::abs(e / start - 1));
      volume = std::max(volume, std::abs(trapezoidal_volume(p, now)));
      const double t = s.time(), l = std::log(e);
      st += t;
      sl += l;
      stt += t * t;
      stl += t * l;
      count += 1;
      before = std::move(now);
    }
    const double slope = (count * stl - st * sl) / (count * stt - st * st);
    std::printf("GL, gamma %.1f: ln E falls at %.4f per second; undamped, within %.2e of its start; volume within %.2e m^3\n",
                gamma, -slope, gamma > 0 ? 0.0 : drift, volume);
    if (gamma > 0)
      EXPECT_NEAR(-slope, gamma, 0.02 * gamma);
    else
      EXPECT_LT(drift, 1e-5);  // floats: the CPU's doubles keep it to 1e-9
    // Each drop displaces about 1e-5 m^3 each way; floats keep the balance to 1e-4 of it.
    EXPECT_LT(volume, 1e-9);
  }
}

TEST_F(WaveGl, AtTheLargestAllowedStepNothingGrows) {
  WaveParams p;
  p.grid = 64;
  p.damping = 0;
  p.drop_radius = spacing(p);
  p.time_step = max_time_step(p);
  WaveSolverGl s(p);
  for (int i = 0; i < 5; ++i) s.drop(-0.8 + 0.37 * i, 0.6 - 0.29 * i, 2e-3, spacing(p));
  double highest = 0;
  for (int i = 0; i < 4000; ++i) {
    s.step();
    if (i % 100 == 0) highest = std::max(highest, peak(s.heights()));
  }
  highest = std::max(highest, peak(s.heights()));
  EXPECT_LT(highest, 0.05);  // the drops were 2 mm deep; nothing ran away
}

WaveParams stormy() {
  WaveParams p;
  p.grid = 96;  // a spacing within the raindrops' radius
  p.rain_rate = 20;
  p.wind_height = 1e-3;
  p.seed = 7;
  return p;
}

TEST_F(WaveGl, AgreesWithTheCpuSolverInRainWindAndDrops) {
  const WaveParams p = stormy();
  WaveSolver cpu(p);
  WaveSolverGl gl(p);
  cpu.drop(0.3, -0.2, 2e-3, 0.05);
  gl.drop(0.3, -0.2, 2e-3, 0.05);
  for (int i = 0; i < 300; ++i) {
    cpu.step();
    gl.step();
  }
  EXPECT_EQ(gl.raindrops(), cpu.raindrops());
  EXPECT_GT(cpu.raindrops(), 0u);
  const auto h = gl.heights();
  double worst = 0;
  for (std::size_t k = 0; k < h.size(); ++k) worst = std::max(worst, std::abs(h[k] - cpu.heights()[k]));
  std::printf("GL against CPU after 300 steps, %llu raindrops: worst %.2e m of a peak %.2e m\n",
              static_cast<unsigned long long>(cpu.raindrops()), worst, peak(cpu.heights()));
  EXPECT_GT(peak(cpu.heights()), 1e-4);
  EXPECT_LT(worst, 1e-4 * peak(cpu.heights()));
}

TEST_F(WaveGl, RunsRepeatBitForBit) {
  WaveParams p = stormy();
  WaveSolverGl a(p), b(p);
  for (int i = 0; i < 200; ++i) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.heights(), b.heights());
  p.seed = 8;
  WaveSolverGl c(p);
  for (int i = 0; i < 200; ++i) c.step();
  EXPECT_NE(a.heights(), c.heights());
}

TEST_F(WaveGl, TakesTheCpusStateOverAndHandsItBack) {
  // Warmed on the CPU (rain, wind, a drop), stepped on the GL, handed back
  // and stepped on the CPU again: the same water as the CPU alone, to the
  // GL's float rounding, with the rain's schedule kept across both.
  const WaveParams p = stormy();
  WaveSolver alone(p), handed(p);
  alone.drop(0.3, -0.2, 2e-3, 0.05);
  handed.drop(0.3, -0.2, 2e-3, 0.05);
  for (int i = 0; i < 100; ++i) alone.step(), handed.step();
  WaveSolverGl gl(p, handed.state());
  EXPECT_EQ(gl.steps(), handed.steps());
  EXPECT_EQ(gl.time(), handed.time());
  for (int i = 0; i < 100; ++i) alone.step(), gl.step();
  handed.restore(gl.state());
  for (int i = 0; i < 100; ++i) alone.step(), handed.step();
  EXPECT_EQ(handed.steps(), alone.steps());
  EXPECT_EQ(handed.time(), alone.time());
  EXPECT_EQ(handed.raindrops(), alone.raindrops());
  EXPECT_GT(alone.raindrops(), 0u);
  double worst = 0;
  for (std::size_t k = 0; k < alone.heights().size(); ++k)
    worst = std::max(worst, std::abs(handed.heights()[k] - alone.heights()[k]));
  EXPECT_GT(peak(alone.heights()), 1e-4);
  EXPECT_LT(worst, 1e-4 * peak(alone.heights()));
  EXPECT_THROW(WaveSolverGl(p, WaveState{{0.0}, {0.0}, 0, 0, 0.0, Rain(p, 1, 0)}), std::invalid_argument);
}

TEST_F(WaveGl, APoolSteppedOnTheGlMovesAsOnTheCpu) {
  // Two pools from one warmed surface, one stepping on the GL: after frames,
  // drops posted between them and a retune (more rain) while attached, the
  // same surface; then detached, it goes on on the CPU.
  WaveParams p = stormy();
  p.warmup_s = 0.5;
  const WaveSolver warmed = warmed_up(p);
  Pool cpu(warmed), gl(warmed);
  gl.attach([](const WaveParams& params, const WaveState& state) {
    return std::make_unique<WaveSolverGl>(params, state);
  });
  ASSERT_TRUE(gl.attached());
  const auto frames = [&](const WaveParams& params, int count) {
    for (int f = 0; f < count; ++f) {
      EXPECT_EQ(cpu.advance(params, 1.0 / 30), gl.advance(params, 1.0 / 30));
      EXPECT_EQ(gl.step(), cpu.step());
    }
  };
  frames(p, 10);
  for (Pool* pool : {&cpu, &gl}) ASSERT_TRUE(pool->post({0.1, 0.2, 2e-3, 0.05}).has_value());
  frames(p, 10);
  p.rain_rate *= 3;
  frames(p, 10);
  gl.detach();
  EXPECT_FALSE(gl.attached());
  frames(p, 10);
  EXPECT_EQ(gl.drops(), 1u);
  EXPECT_EQ(gl.solver().raindrops(), cpu.solver().raindrops());
  const auto& a = cpu.solver().heights();
  const auto& b = gl.solver().heights();
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  EXPECT_GT(peak(a), 1e-4);
  EXPECT_LT(worst, 1e-4 * peak(a));
  // Its mesh is the surface it stepped to.
  EXPECT_EQ(gl.mesh()->positions.size(), a.size());
}

}  // namespace
}  // namespace caustic::water
