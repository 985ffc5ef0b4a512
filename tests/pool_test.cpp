// SPDX-License-Identifier: LGPL-2.1-or-later
// The pool a stream advances: whole fixed steps with the remainder carried,
// a stall capped, paused water still taking drops, drops checked when posted
// and numbered, a bounded queue, retuning that keeps the surface (and its
// energy), the coarse surface the viewers get, and the scene's warmed-up
// surface made the same way every time.
#include "caustic/pool.hpp"
#include "caustic/water_mesh.hpp"
#include "refusal.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace caustic::water {
namespace {

WaveParams calm() {
  WaveParams p;
  p.grid = 64;
  p.time_step = 0.01;
  return p;
}

}  // namespace

TEST(Pool, AdvancesByWholeStepsAndCarriesTheRest) {
  Pool pool(calm());
  EXPECT_FALSE(pool.advance(calm(), 0.004));  // less than a step: nothing moves yet
  EXPECT_EQ(pool.step(), 0u);
  EXPECT_TRUE(pool.advance(calm(), 0.007));   // 0.011 s owed: one step, 0.001 carried
  EXPECT_EQ(pool.step(), 1u);
  pool.advance(calm(), 0.029);                // 0.030 s owed: three more
  EXPECT_EQ(pool.step(), 4u);
  // Many frames of a 30 fps stream: the water keeps the stream's time.
  for (int f = 0; f < 300; ++f) pool.advance(calm(), 1.0 / 30);
  EXPECT_NEAR(pool.solver().time(), 0.04 + 10.0, 0.0100001);
}

TEST(Pool, AStallSlowsTheWaterInsteadOfOwingIt) {
  Pool pool(calm());
  pool.advance(calm(), 30.0);
  EXPECT_EQ(pool.step(), static_cast<std::uint64_t>(std::lround(Pool::kMaxAdvance / 0.01)));
  EXPECT_FALSE(pool.advance(calm(), std::nan("")));
  EXPECT_FALSE(pool.advance(calm(), -1.0));
}

TEST(Pool, PausedWaterStandsButTakesDrops) {
  WaveParams paused = calm();
  paused.paused = true;
  Pool pool(calm());
  ASSERT_EQ(pool.post({0.1, -0.2, 0.005, 0.05}), 1u);
  EXPECT_TRUE(pool.advance(paused, 1.0));  // the drop falls...
  EXPECT_EQ(pool.step(), 0u);              // ...but no time passes
  EXPECT_EQ(pool.drops(), 1u);
  EXPECT_FALSE(pool.advance(paused, 1.0));
  // Viewers are told of the surface with the drop, though the step stands.
  pool.mesh();
  ASSERT_TRUE(pool.post({-0.3, 0.2, 0.005, 0.05}).has_value());
  pool.advance(paused, 1.0);
  pool.mesh();
  EXPECT_EQ(pool.proxy(0).drops, 2u);
  EXPECT_TRUE(pool.advance(calm(), 0.05));
  EXPECT_EQ(pool.step(), 5u);
}

TEST(Pool, DropsAreCheckedWhenPostedAndNumbered) {
  Pool pool(calm());
  const auto key_of = [&](Drop d) { return caustic::testing::refused_key<SceneError>([&] { pool.post(d); }); };
  EXPECT_EQ(key_of({1.5, 0, 0.001, 0.05}), "x");
  EXPECT_EQ(key_of({0, -1.01, 0.001, 0.05}), "y");
  EXPECT_EQ(key_of({0, std::nan(""), 0.001, 0.05}), "y");
  EXPECT_EQ(key_of({0, 0, 0.2, 0.05}), "strength");
  EXPECT_EQ(key_of({0, 0, 0.001, 0.001}), "radius");  // under one grid spacing
  EXPECT_EQ(key_of({0, 0, 0.001, 0.6}), "radius");
  EXPECT_EQ(pool.post({0, 0, 0.001, 0.05}), 1u);  // refused drops take no number
  EXPECT_EQ(pool.post({1, 1, -0.001, 0.05}), 2u);
}

TEST(Pool, TheQueueIsBounded) {
  Pool pool(calm());
  for (std::size_t i = 0; i < Pool::kMaxQueued; ++i) ASSERT_TRUE(pool.post({0, 0, 0.001, 0.05}).has_value());
  EXPECT_FALSE(pool.post({0, 0, 0.001, 0.05}).has_value());
  pool.advance(calm(), 0.0);  // they fall; room again
  EXPECT_EQ(pool.drops(), Pool::kMaxQueued);
  EXPECT_EQ(pool.post({0, 0, 0.001, 0.05}), Pool::kMaxQueued + 1);
}

TEST(Pool, RetuningKeepsTheSurfaceAndItsEnergy) {
  WaveParams p = calm();
  p.damping = 0;
  Pool pool(p);
  pool.post({0, 0, 0.01, 0.08});
  pool.advance(p, 0.5);
  const double energy = pool.solver().energy();
  const auto heights = pool.solver().heights();
  WaveParams finer = p;
  finer.time_step = 0.005;
  pool.advance(finer, 0.0);
  EXPECT_EQ(pool.solver().heights(), heights);
  EXPECT_EQ(pool.solver().time_step(), 0.005);
  pool.advance(finer, 0.2);
  // Halving the step changes the scheme's discrete energy only at O(dt^2).
  EXPECT_NEAR(pool.solver().energy(), energy, 0.02 * energy);
  WaveParams bigger = finer;
  bigger.grid = 65;
  try {
    pool.advance(bigger, 0.1);
    ADD_FAILURE() << "a new grid was taken";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "water.grid");
  }
  EXPECT_EQ(pool.solver().params(), finer);
}

TEST(Pool, ViewersGetTheCoarseSurfaceOfEachFrameDrawn) {
  Pool pool(calm());
  pool.post({0, 0, 0.01, 0.1});
  pool.advance(calm(), 0.0);
  const auto mesh = pool.mesh();
  EXPECT_EQ(pool.mesh(), mesh);  // unmoved: the same surface
  const Proxy proxy = pool.proxy(pool.step());
  ASSERT_EQ(proxy.n, Pool::kProxySide);
  ASSERT_EQ(proxy.heights.size(), static_cast<std::size_t>(proxy.n * proxy.n));
  EXPECT_EQ(proxy.drops, 1u);
  // Its corners are the grid's corners; inside, the surface interpolated.
  const auto& h = pool.solver().heights();
  const int n = calm().grid, side = proxy.n;
  EXPECT_NEAR(proxy.heights[0] * proxy.unit, h[0], proxy.unit);
  EXPECT_NEAR(proxy.heights.back() * proxy.unit, h.back(), proxy.unit);
  const double u = (side / 2) * static_cast<double>(n - 1) / (side - 1);  // where proxy column side/2 falls
  const int i0 = static_cast<int>(u);
  const double f = u - i0;
  const auto at = [&](int i, int j) { return h[static_cast<std::size_t>(j) * n + i]; };
  const double expected = (1 - f) * ((1 - f) * at(i0, i0) + f * at(i0 + 1, i0)) + f * ((1 - f) * at(i0, i0 + 1) + f * at(i0 + 1, i0 + 1));
  EXPECT_NEAR(proxy.heights[static_cast<std::size_t>(side / 2) * side + side / 2] * proxy.unit, expected, proxy.unit);
  EXPECT_LT(proxy.heights[static_cast<std::size_t>(side / 2) * side + side / 2], -100);  // the dent, well resolved
  // A step not drawn has no proxy; old ones are let go.
  EXPECT_TRUE(pool.proxy(pool.step() + 1).heights.empty());
  const std::uint64_t first = pool.step();
  for (std::size_t f2 = 0; f2 <= Pool::kProxiesKept; ++f2) {
    pool.advance(calm(), 0.01);
    pool.mesh();
  }
  EXPECT_TRUE(pool.proxy(first).heights.empty());
  EXPECT_FALSE(pool.proxy(pool.step()).heights.empty());
}

TEST(Pool, APreviewDrawsTheSurfaceThinnedAndViewersGetOneCopyOfIt) {
  Pool pool(calm());
  pool.advance(calm(), 0.01);
  const std::uint64_t first = pool.step();
  const auto thin = pool.mesh(2), full = pool.mesh();
  EXPECT_EQ(pool.mesh(2), thin);  // each built once a surface
  EXPECT_EQ(pool.mesh(), full);
  const auto n = static_cast<std::size_t>(calm().grid), m = (n - 2) / 2 + 2;  // every other post and the wall's
  EXPECT_EQ(full->positions.size(), n * n);
  EXPECT_EQ(thin->positions.size(), m * m);
  // kProxiesKept surfaces, each drawn at both levels: the first is still
  // kept, so each was copied for the viewers once.
  for (std::size_t k = 1; k < Pool::kProxiesKept; ++k) {
    pool.advance(calm(), 0.01);
    EXPECT_NE(pool.mesh(2), thin);
    pool.mesh();
  }
  EXPECT_FALSE(pool.proxy(first).heights.empty());
}

TEST(Pool, ACoarserCopyKeepsTheWallsAndInterpolatesInside) {
  Proxy fine;
  fine.n = 32;
  fine.step = 9;
  // A plane, which bilinear sampling keeps exactly: h = 100 i - 30 j units.
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) fine.heights.push_back(static_cast<std::int16_t>(100 * i - 30 * j));
  const Proxy coarse = resample(fine, 16);
  ASSERT_EQ(coarse.n, 16);
  ASSERT_EQ(coarse.heights.size(), 256u);
  EXPECT_EQ(coarse.step, 9u);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i)
      EXPECT_NEAR(coarse.heights[static_cast<std::size_t>(j) * 16 + i], (100 * i - 30 * j) * 31.0 / 15, 0.5) << i << "," << j;
  EXPECT_EQ(resample(fine, 32).heights, fine.heights);
  EXPECT_TRUE(resample(Proxy{}, 16).heights.empty());
}

TEST(Pool, AScenesSurfaceIsItsWarmedUpWaterEveryTime) {
  Scene scene;
  WaveParams p = calm();
  p.rain_rate = 20;
  p.drop_radius = 0.05;
  p.warmup_s = 1.0;
  scene.water = p;
  const Mesh a = load_scene_mesh(scene), b = load_scene_mesh(scene);
  EXPECT_EQ(a.positions, b.positions);
  WaveSolver solver(p);
  for (int i = 0; i < 100; ++i) solver.step();
  EXPECT_EQ(a.positions, water_mesh(solver).positions);
  EXPECT_EQ(Pool(p).mesh()->positions, a.positions);
  // Not still water: it rained for a second.
  double deepest = 0;
  for (const auto& v : a.positions) deepest = std::min<double>(deepest, v.z);
  EXPECT_LT(deepest, -1e-4);
}

}  // namespace caustic::water
