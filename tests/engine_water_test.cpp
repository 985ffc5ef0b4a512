// SPDX-License-Identifier: LGPL-2.1-or-later
// Light through a water surface onto the pool's floor (object.shape
// "surface", docs/physics.md §14): still water against Fresnel, a small
// sinusoidal wave against its paraxial map and its fold depth, and the
// flux that lands against the flux that entered; one seed, one caustic.
// Under a lamp and between walls: engine_pool_test.cpp.
#include "water_scene.hpp"

#include "caustic/vertex_rays.hpp"
#include "caustic/water_mesh.hpp"

#include <cmath>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

// The mean and the worst relative departure from it of the floor's pixels
// whose centres lie `margin` inside the square of half-width `half` about `at`.
std::pair<double, double> patch(const HdrImage& img, const ScreenParams& floor, glm::dvec2 at, double half,
                                double margin) {
  double sum = 0;
  std::vector<float> values;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 p = pixel_centre(floor, img.width, img.height, x, y) - at;
      if (std::abs(p.x) <= half - margin && std::abs(p.y) <= half - margin) {
        values.push_back(img.at(x, y));
        sum += img.at(x, y);
      }
    }
  const double mean = sum / static_cast<double>(values.size());
  double worst = 0;
  for (float v : values) worst = std::max(worst, std::abs(v - mean) / mean);
  return {mean, worst};
}

// The sun's flux that enters `mesh` (placed by `placement`) as the per-
// vertex method models it (docs/physics.md ch. 5): each triangle's cross-
// section of the beam times the mean of its corners' transmittances, each
// at the angle between the sun and the corner's normal.
double entering_flux(const Scene& s, const Mesh& mesh, const Placement& placement) {
  const glm::dvec3 sun = glm::normalize(s.light.direction);
  std::vector<double> t(mesh.positions.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const glm::dvec3 n = glm::normalize(placement.rotation * glm::dvec3(mesh.normals[i]));
    t[i] = transmittance(std::abs(glm::dot(n, sun)), kWater);
  }
  double flux = 0;
  for (const glm::uvec3& tri : mesh.triangles) {
    const auto at = [&](std::uint32_t i) { return glm::dvec3(placement.model * glm::dvec4(glm::dvec3(mesh.positions[i]), 1)); };
    const glm::dvec3 a = at(tri.x), b = at(tri.y), c = at(tri.z);
    flux += (t[tri.x] + t[tri.y] + t[tri.z]) / 3 * std::abs(glm::dot(0.5 * glm::cross(b - a, c - a), sun));
  }
  return flux;
}

}  // namespace

class Water : public GlTest {};

TEST_F(Water, StillWaterLightsTheFloorEvenlyWithFresnelsTransmittance) {
  const auto still = shared(grid_mesh(flat_face(kHalf), 64, 64));
  for (double degrees : {0.0, 30.0, 60.0}) {
    const double theta = degrees * std::numbers::pi / 180, depth = 10.0;
    const Scene s = water_pool(depth, theta, 40.0);
    const HdrImage img = render(s, still);
    // The lit patch is the surface's square, shifted along the refracted ray.
    const double sin_t = std::sin(theta) / kWater;
    const glm::dvec2 centre(depth * sin_t / std::sqrt(1 - sin_t * sin_t), 0.0);
    const auto [mean, spread] = patch(img, s.screen, centre, kHalf, 2 * 40.0 / 256);
    // Relative to the sun's irradiance on a horizontal plane, E0 cos(theta).
    const double t = transmittance(std::cos(theta), kWater);
    std::printf("sun %2.0f deg: floor %.5f of horizontal, T = %.5f\n", degrees, mean / std::cos(theta), t);
    EXPECT_NEAR(mean / std::cos(theta), t, 0.005 * t) << degrees << " degrees";
    EXPECT_LT(spread, 1e-3) << degrees << " degrees";
    EXPECT_EQ(engine_->stats().dropped, 0u);
  }
}

// h(x) = A cos(kx) refracts the sun straight down to x_f = x + d (1 - 1/n)
// h'(x) on a floor d below (small slopes), so the floor reads
// E = T / (1 + d (1 - 1/n) h''(x)) = T / (1 - m cos kx), m = d (1 - 1/n) A k^2,
// whose first order is T (1 + m cos k x_f); the sheets fold where m = 1.
class SineWave : public Water {
 protected:
  static constexpr double kAmplitude = 0.02, kWavelength = 5.0;
  static double k() { return 2 * std::numbers::pi / kWavelength; }
  static double fold_depth() { return 1.0 / ((1 - 1 / kWater) * kAmplitude * k() * k()); }
  std::shared_ptr<const Mesh> wave = shared(grid_mesh(sine_window(kAmplitude, k(), 0.0, 1.0, kHalf), 257, 257));

  // The floor's mean over rows |y| < 5 mm, per column.
  std::vector<double> profile(const HdrImage& img, const ScreenParams& floor) {
    std::vector<double> out(static_cast<std::size_t>(img.width), 0.0);
    for (int x = 0; x < img.width; ++x) {
      int n = 0;
      for (int y = 0; y < img.height; ++y)
        if (std::abs(pixel_centre(floor, img.width, img.height, x, y).y) < 5.0) {
          out[static_cast<std::size_t>(x)] += img.at(x, y);
          ++n;
        }
      out[static_cast<std::size_t>(x)] /= n;
    }
    return out;
  }
};

TEST_F(SineWave, TheFloorFollowsThePredictedModulation) {
  const double t = transmittance(1.0, kWater);
  for (double m : {0.05, 0.5}) {
    const double depth = m * fold_depth();
    const Scene s = water_pool(depth, 0.0, 25.6);
    const HdrImage img = render(s, wave);
    const auto floor = profile(img, s.screen);
    const double c = (1 - 1 / kWater) * depth;
    double worst = 0, projection = 0, norm = 0;
    for (int x = 0; x < img.width; ++x) {
      const double xf = pixel_centre(s.screen, img.width, img.height, x, 0).x;
      if (std::abs(xf) > 7.5) continue;  // two wavelengths inside the water's edge
      // The paraxial map's source point: solve xf = x - c A k sin(kx) by Newton.
      double src = xf;
      for (int i = 0; i < 20; ++i)
        src -= (src - c * kAmplitude * k() * std::sin(k() * src) - xf) /
               (1 - c * kAmplitude * k() * k() * std::cos(k() * src));
      const double predicted = t / (1 - m * std::cos(k() * src));
      worst = std::max(worst, std::abs(floor[static_cast<std::size_t>(x)] - predicted) / predicted);
      projection += (floor[static_cast<std::size_t>(x)] / t - 1) * std::cos(k() * xf);
      norm += std::cos(k() * xf) * std::cos(k() * xf);
    }
    std::printf("m = %.2f (depth %.1f mm): worst %.4f against the paraxial map; first-order amplitude %.4f\n", m,
                depth, worst, projection / norm);
    EXPECT_LT(worst, 0.01) << "m = " << m;
    // The first order: a cosine of amplitude m, to O(m^2).
    if (m < 0.1) {
      EXPECT_NEAR(projection / norm, m, 0.02 * m);
    }
    EXPECT_EQ(engine_->stats().folded, 0u) << "m = " << m;
  }
}

TEST_F(SineWave, SheetsFoldAtThePredictedDepth) {
  for (double m : {0.95, 1.05}) {
    const Scene s = water_pool(m * fold_depth(), 0.0, 25.6);
    render(s, wave);
    const auto folded = engine_->stats().folded;
    std::printf("depth %.3f of the fold depth %.1f mm: %u folded triangles\n", m, fold_depth(), folded);
    if (m < 1) {
      EXPECT_EQ(folded, 0u);
    } else {
      EXPECT_GT(folded, 1000u);  // along every crest
    }
  }
}

TEST_F(Water, WhateverTheWavesTheFloorGetsTheFluxThatEntered) {
  // Two crossing waves, deep enough to fold; the sun 40 degrees off.
  const auto waves = shared(grid_mesh(sine_window(0.05, 1.3, 0.04, 0.9, kHalf), 129, 129));
  for (bool fresnel : {false, true}) {
    Scene s = water_pool(60.0, 0.7, 100.0);
    s.render.fresnel = fresnel;
    const HdrImage img = render(s, waves);
    const Placement placement = place_object(s.object, *waves);
    const double landed = total_flux(img, s.screen);
    // Without Fresnel every ray lands, carrying its triangle's cross-section
    // of the beam: the footprint's 400 mm^2 times cos(theta). With Fresnel
    // each triangle's share is its corners' mean transmittance.
    const double entered = fresnel ? entering_flux(s, *waves, placement) : 4 * kHalf * kHalf * std::cos(0.7);
    std::printf("Fresnel %s: landed %.6f of %.6f mm^2, %u folded\n", fresnel ? "on " : "off", landed, entered,
                engine_->stats().folded);
    EXPECT_NEAR(landed, entered, 1e-4 * entered);
    EXPECT_GT(engine_->stats().folded, 0u);
    EXPECT_EQ(engine_->stats().dropped, 0u);
  }
}

TEST_F(Water, OneSeedAndOneStepCountGiveTheSameCausticBitForBit) {
  // Rain over a 2 m pool for 300 steps, twice from the same seed, once from
  // another: the floors are identical, then different.
  water::WaveParams params;
  params.grid = 96;
  params.rain_rate = 30;
  params.seed = 7;
  const auto floor_after = [&](std::uint64_t seed) {
    water::WaveParams p = params;
    p.seed = seed;
    water::WaveSolver solver(p);
    for (int i = 0; i < 300; ++i) solver.step();
    Scene s = water_pool(1.2, 0.35, 2.4);
    s.object.rotation_deg = {0, 0, 0};  // water_mesh is already face up
    s.screen.center = {0.15, 0, -1.2};
    return render(s, shared(water::water_mesh(solver)));
  };
  const HdrImage a = floor_after(7), b = floor_after(7), c = floor_after(8);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_NE(a.pixels, c.pixels);
  double lit = 0;
  for (float v : a.pixels) lit += v > 0;
  EXPECT_GT(lit, 0.5 * static_cast<double>(a.pixels.size()));
}
