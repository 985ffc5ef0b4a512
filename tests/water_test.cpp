// SPDX-License-Identifier: LGPL-2.1-or-later
// The wave solver against the wave equation's own laws (docs/physics.md §14):
// a ring's speed, the scheme's conserved energy, the damping's decay rate,
// the stability bound, the kept volume, and repeatable runs.
#include "caustic/scene.hpp"
#include "caustic/wave_solver.hpp"
#include "caustic/water_mesh.hpp"
#include "water_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace caustic::water {
namespace {

using namespace caustic::water::testing;

TEST(WaveSolver, ADropsRingSpreadsAtTheWaveSpeed) {
  WaveSolver s(ring_pool());
  const Ring ring = follow_ring(s);
  EXPECT_NEAR(ring.speed(), s.params().wave_speed, 0.02 * s.params().wave_speed);
  EXPECT_NEAR(ring.unsteadiness(), 0.0, 0.02 * s.params().wave_speed);
}

TEST(WaveSolver, WithoutDampingTheSchemeKeepsItsEnergy) {
  WaveParams p;
  p.damping = 0;
  p.time_step = max_time_step(p);  // the largest step allowed
  WaveSolver s(p);
  scatter_drops(s);
  s.step();
  const double start = s.energy();
  ASSERT_GT(start, 0);
  double worst = 0;
  for (int i = 0; i < 4000; ++i) {
    s.step();
    worst = std::max(worst, std::abs(s.energy() / start - 1));
  }
  std::printf("energy drift over 4000 steps at Courant %.2f: %.2e\n", kMaxCourant, worst);
  EXPECT_LT(worst, 1e-9);
}

TEST(WaveSolver, EnergyDecaysAtTheSetDamping) {
  WaveParams p;
  p.damping = 0.5;
  p.time_step = max_time_step(p);
  WaveSolver s(p);
  scatter_drops(s);
  // Least squares slope of ln E against t over 6 s: the oscillation between
  // kinetic and potential energy averages out over many periods.
  double st = 0, sl = 0, stt = 0, stl = 0, count = 0;
  while (s.time() < 6.0) {
    s.step();
    const double t = s.time(), l = std::log(s.energy());
    st += t;
    sl += l;
    stt += t * t;
    stl += t * l;
    count += 1;
  }
  const double slope = (count * stl - st * sl) / (count * stt - st * st);
  std::printf("ln E falls at %.4f per second against gamma = %.4f\n", -slope, p.damping);
  EXPECT_NEAR(-slope, p.damping, 0.02 * p.damping);
}

TEST(WaveSolver, AtTheLargestAllowedStepNothingGrows) {
  // The highest (checkerboard) modes go unstable first: drops one grid
  // spacing wide carry them. Run long.
  WaveParams p;
  p.grid = 64;
  p.damping = 0;
  p.drop_radius = spacing(p);
  p.time_step = max_time_step(p);
  WaveSolver s(p);
  for (int i = 0; i < 5; ++i) s.drop(-0.8 + 0.37 * i, 0.6 - 0.29 * i, 2e-3, spacing(p));
  for (int i = 0; i < 2; ++i) s.step();
  const double start = s.energy();
  double highest = 0;
  for (int i = 0; i < 20000; ++i) {
    s.step();
    for (double h : s.heights()) highest = std::max(highest, std::abs(h));
  }
  EXPECT_NEAR(s.energy(), start, 1e-8 * start);
  EXPECT_LT(highest, 0.05);  // the drops were 2 mm deep; nothing ran away
}

TEST(WaveSolver, AStepAboveTheBoundIsRefusedNamingTheKey) {
  WaveParams p;
  p.time_step = max_time_step(p) * 1.001;
  try {
    WaveSolver s(p);
    FAIL() << "a step beyond the stability bound was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "water.time_step");
    EXPECT_NE(std::string(e.what()).find("unstable"), std::string::npos) << e.what();
  }
  p.time_step = max_time_step(p);
  EXPECT_NO_THROW(validate(p));
}

TEST(WaveSolver, BadParametersAndDropsAreRefusedAndChangeNothing) {
  const auto key_of = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const SceneError& e) {
      return e.key();
    }
    return "";
  };
  const auto with = [](auto change) {
    WaveParams p;
    change(p);
    return p;
  };
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.grid = 8; })); }), "water.grid");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.grid = 4096; })); }), "water.grid");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.size = NAN; })); }), "water.size");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.wave_speed = 0; })); }), "water.wave_speed");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.damping = -1; })); }), "water.damping");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.time_step = -0.01; })); }), "water.time_step");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.rain_rate = 1e9; })); }), "water.rain_rate");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.rain_strength = INFINITY; })); }), "water.rain_strength");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.drop_radius = 1e-6, p.rain_rate = 1; })); }),
            "water.drop_radius");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.drop_radius = 1.0; })); }), "water.drop_radius");
  EXPECT_EQ(key_of([&] { validate(with([](WaveParams& p) { p.drop_radius = 1e-6; })); }), "");  // no rain: moot

  WaveSolver s(WaveParams{});
  scatter_drops(s);
  s.step();
  const auto heights = s.heights();
  EXPECT_EQ(key_of([&] { s.drop(5.0, 0, 1e-3, 0.05); }), "x");
  EXPECT_EQ(key_of([&] { s.drop(0, NAN, 1e-3, 0.05); }), "y");
  EXPECT_EQ(key_of([&] { s.drop(0, 0, 1.0, 0.05); }), "strength");
  EXPECT_EQ(key_of([&] { s.drop(0, 0, 1e-3, 0.0); }), "radius");
  EXPECT_EQ(key_of([&] { s.drop(0, 0, 1e-3, 10.0); }), "radius");
  EXPECT_EQ(s.heights(), heights);
}

TEST(WaveSolver, RainFallsAtItsRateAndKeepsTheVolume) {
  WaveParams p;
  p.rain_rate = 40;
  WaveSolver s(p);
  double worst = 0;
  while (s.time() < 10.0) {
    s.step();
    worst = std::max(worst, std::abs(s.volume()));
  }
  // 400 expected; a Poisson count lies within 4 sigma (80) but for 6e-5 of seeds.
  EXPECT_NEAR(static_cast<double>(s.raindrops()), p.rain_rate * s.time(), 4 * std::sqrt(p.rain_rate * s.time()));
  // Each drop is a 2 mm dent about 3 cm wide, some 1e-5 m^3 displaced each
  // way; the pool keeps its water to rounding.
  EXPECT_LT(worst, 1e-12);
  double energy = s.energy();
  EXPECT_GT(energy, 0);
}

TEST(WaveSolver, RunsRepeatBitForBit) {
  WaveParams p;
  p.rain_rate = 30;
  p.seed = 42;
  WaveSolver a(p), b(p);
  for (int i = 0; i < 600; ++i) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.raindrops(), b.raindrops());
  EXPECT_EQ(a.heights(), b.heights());  // every double equal
  p.seed = 43;
  WaveSolver c(p);
  for (int i = 0; i < 600; ++i) c.step();
  EXPECT_NE(a.heights(), c.heights());
}

TEST(WaveSolver, ARestoredStateGoesOnBitForBit) {
  // Another solver's state, taken mid-storm: the steps that follow are the
  // first solver's own, rain and wind included.
  WaveParams p;
  p.rain_rate = 30;
  p.wind_height = 2e-3;
  p.damping = 0.3;
  WaveSolver a(p), b(p);
  for (int i = 0; i < 300; ++i) a.step();
  b.restore(a.state());
  for (int i = 0; i < 300; ++i) a.step(), b.step();
  EXPECT_EQ(a.heights(), b.heights());
  EXPECT_EQ(a.raindrops(), b.raindrops());
  EXPECT_EQ(a.steps(), b.steps());
  EXPECT_GT(a.raindrops(), 10u);
  WaveParams other = p;
  other.grid = 64;
  other.rain_rate = 0;
  WaveSolver c(other);
  EXPECT_THROW(c.restore(a.state()), std::invalid_argument);
  EXPECT_EQ(c.steps(), 0u);
}

}  // namespace
}  // namespace caustic::water

namespace caustic::water {
namespace {

TEST(WaterMesh, StillWaterIsFlatAndEveryVertexFollowsItsHeight) {
  WaveParams p;
  p.grid = 33;
  WaveSolver s(p);
  Mesh still = water_mesh(s);
  ASSERT_EQ(still.positions.size(), 33u * 33u);
  EXPECT_EQ(still.triangles.size(), 2u * 32u * 32u);
  for (const auto& n : still.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
  EXPECT_NO_THROW(validate_mesh(still));
  s.drop(0.3, -0.2, 2e-3, 0.1);
  for (int i = 0; i < 10; ++i) s.step();
  const Mesh wavy = water_mesh(s);
  EXPECT_NO_THROW(validate_mesh(wavy));
  for (std::size_t k = 0; k < wavy.positions.size(); ++k)
    EXPECT_FLOAT_EQ(wavy.positions[k].z, static_cast<float>(s.heights()[k]));
  // Triangles face up, the way the normals point.
  for (const auto& t : wavy.triangles) {
    const glm::vec3 a = wavy.positions[t.x], b = wavy.positions[t.y], c = wavy.positions[t.z];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
  }
  // At a wall the slope across it is zero, as the solver's walls hold it.
  for (int j = 0; j < p.grid; ++j) EXPECT_EQ(wavy.normals[static_cast<std::size_t>(j) * p.grid].x, 0.0f);
}

TEST(WaterMesh, APreviewKeepsEveryOtherPostAndTheWallsWithTheirOwnNormals) {
  WaveParams p;
  p.grid = 34;  // 0, 2, ..., 32 and the wall's 33: the last cell one post wide
  WaveSolver s(p);
  s.drop(0.3, -0.2, 2e-3, 0.1);
  for (int i = 0; i < 10; ++i) s.step();
  const Mesh full = water_mesh(s), thin = water_mesh(s, 2);
  EXPECT_EQ(water_mesh(s, 1).positions, full.positions);
  std::vector<int> posts;
  for (int i = 0; i <= 32; i += 2) posts.push_back(i);
  posts.push_back(33);
  const std::size_t m = posts.size();
  ASSERT_EQ(thin.positions.size(), m * m);
  EXPECT_EQ(thin.triangles.size(), 2 * (m - 1) * (m - 1));
  EXPECT_NO_THROW(validate_mesh(thin));
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t a = 0; a < m; ++a) {
      const std::size_t k = b * m + a, at = static_cast<std::size_t>(posts[b] * p.grid + posts[a]);
      EXPECT_EQ(thin.positions[k], full.positions[at]) << a << ", " << b;
      EXPECT_EQ(thin.normals[k], full.normals[at]) << a << ", " << b;
    }
  // Wall to wall, facing up.
  EXPECT_FLOAT_EQ(thin.positions.front().x, static_cast<float>(-p.size / 2));
  EXPECT_FLOAT_EQ(thin.positions.back().y, static_cast<float>(p.size / 2));
  for (const auto& t : thin.triangles) {
    const glm::vec3 a = thin.positions[t.x], b = thin.positions[t.y], c = thin.positions[t.z];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
  }
}

}  // namespace
}  // namespace caustic::water
