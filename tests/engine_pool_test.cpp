// SPDX-License-Identifier: LGPL-2.1-or-later
// Still water in a pool, the two ways docs/physics.md §14 lights it beyond
// the sun on a lone floor: a lamp above the water (the floor against the
// inverse-square law refracted through a flat surface, an independent
// radial map) and walls as receivers (the sunlit wall, the floor in the
// shadow of the far wall, and every watt of the transmitted beam).
#include "water_scene.hpp"

#include "caustic/receivers.hpp"

#include <cmath>
#include <functional>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

struct Region {
  double mean = 0, worst = 0;  // worst: relative departure from `mean`
  int pixels = 0;
};

// The pixels of surface `index`'s atlas tile whose centres (surface
// coordinates: right, up from its centre) pass `inside`.
Region region(const HdrImage& img, const Scene& s, std::size_t index, const std::function<bool(glm::dvec2)>& inside) {
  const auto surfaces = receiving_surfaces(s);
  const AtlasTile t = atlas_layout(img.width, img.height, surfaces.size())[index];
  const ScreenParams& r = surfaces[index];
  std::vector<double> values;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x)
      if (inside(pixel_centre(r, t.width, t.height, x, y)))
        values.push_back(img.at(t.x + x, t.y + y));
  Region out;
  out.pixels = static_cast<int>(values.size());
  for (double v : values) out.mean += v / static_cast<double>(values.size());
  for (double v : values) out.worst = std::max(out.worst, std::abs(v - out.mean) / out.mean);
  return out;
}

// Sum of irradiance times pixel area over surface `index`'s tile.
double tile_flux(const HdrImage& img, const Scene& s, std::size_t index) {
  const auto surfaces = receiving_surfaces(s);
  const AtlasTile t = atlas_layout(img.width, img.height, surfaces.size())[index];
  double sum = 0;
  for (int y = t.y; y < t.y + t.height; ++y)
    for (int x = t.x; x < t.x + t.width; ++x) sum += img.at(x, y);
  return sum * surfaces[index].width / t.width * surfaces[index].height / t.height;
}

ScreenParams wall(glm::dvec3 centre, glm::dvec3 inward, double width, double height) {
  ScreenParams r;
  r.center = centre;
  r.normal = inward;
  r.up = {0, 0, 1};
  r.width = width;
  r.height = height;
  r.follow_light = false;
  return r;
}

}  // namespace

class Pool : public GlTest {};

// A lamp H above flat water, the floor D below it. The ray that enters r
// from the axis leaves at sin t = r / (n sqrt(r^2 + H^2)) and lands at
// R(r) = r + D tan t; an annulus of the water, 2 pi r dr, takes
// E0 H^2 T(i) cos i / (r^2 + H^2) per unit area (E0: the lamp's irradiance
// at H) and spreads it over 2 pi R dR, so E / E0 = H^2 T cos i r /
// ((r^2 + H^2) R R'(r)). Nothing here is the engine's: the map is inverted
// by bisection for every floor pixel and compared with what it drew.
TEST_F(Pool, UnderALampTheFloorFollowsTheRefractedInverseSquareLaw) {
  constexpr double kHeight = 15.0, kDepth = 10.0;
  Scene s = water_pool(kDepth, 0.0, 40.0);
  s.light.type = LightType::point;
  s.light.position = {0, 0, kHeight};
  const auto still = shared(grid_mesh(flat_face(kHalf), 129, 129));
  const HdrImage img = render(s, still);

  const auto sin_t = [](double r) { return r / (kWater * std::hypot(r, kHeight)); };
  const auto landed = [&](double r) { return r + kDepth * sin_t(r) / std::sqrt(1 - sin_t(r) * sin_t(r)); };
  const auto predicted = [&](double big_r) {
    double lo = 0, hi = kHalf;
    for (int i = 0; i < 60; ++i) (landed(0.5 * (lo + hi)) < big_r ? lo : hi) = 0.5 * (lo + hi);
    const double r = 0.5 * (lo + hi), rho2 = r * r + kHeight * kHeight, cos_i = kHeight / std::sqrt(rho2);
    const double cos_t = std::sqrt(1 - sin_t(r) * sin_t(r));
    const double slope = 1 + kDepth * kHeight * kHeight / (kWater * rho2 * std::sqrt(rho2) * cos_t * cos_t * cos_t);
    return kHeight * kHeight * transmittance(cos_i, kWater) * cos_i / rho2 * (r / big_r) / slope;
  };
  // Two pixels inside the lit square's image along each axis (the corners
  // of the square land farther out; the test keeps to the disc inside).
  const double pixel = s.screen.width / img.width, reach = landed(kHalf) - 2 * pixel;
  double worst = 0, centre = 0;
  int counted = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double big_r = glm::length(pixel_centre(s.screen, img.width, img.height, x, y));
      if (big_r > reach) continue;
      const double expected = predicted(big_r);
      worst = std::max(worst, std::abs(img.at(x, y) - expected) / expected);
      if (big_r < pixel) centre = img.at(x, y) / expected;
      ++counted;
    }
  std::printf("lamp %.0f mm above, floor %.0f mm below: %d pixels, worst %.5f of the radial law, centre %.5f\n",
              kHeight, kDepth, counted, worst, centre);
  EXPECT_GT(counted, 10000);
  EXPECT_LT(worst, 0.005);

  // The flux through the water: H^2 times the integral of T cos i / rho^2
  // over the square, by the midpoint rule on a fine grid.
  constexpr int kCells = 2000;
  double entered = 0;
  const double cell = 2 * kHalf / kCells;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const double px = -kHalf + (i + 0.5) * cell, py = -kHalf + (j + 0.5) * cell;
      const double rho2 = px * px + py * py + kHeight * kHeight, cos_i = kHeight / std::sqrt(rho2);
      entered += transmittance(cos_i, kWater) * cos_i / rho2 * cell * cell;
    }
  entered *= kHeight * kHeight;
  const double floor = total_flux(img, s.screen);
  std::printf("landed %.6f of %.6f mm^2 entered\n", floor, entered);
  EXPECT_NEAR(floor, entered, 1e-4 * entered);
}

// The sun 40 degrees off, travelling towards +x, over a square of water
// with a floor D below and four walls just outside its edge, as receivers.
// The beam refracted at t lands shifted by D tan t: the floor under the
// -x wall's first D tan t is in shadow, the rest reads T cos(40 deg); the
// light that would land past the +x wall lights it instead, all of it,
// at T cos(40 deg) tan t (a strip D tan t wide of water over a wall D
// high); the walls along the beam and the one behind it stay dark.
TEST_F(Pool, WallsCatchWhatTheFloorDoesNot) {
  constexpr double kDepth = 10.0, kEdge = kHalf + 0.01;  // walls 10 um outside the water
  const double theta = 40 * std::numbers::pi / 180;
  Scene s = water_pool(kDepth, theta, 2 * kEdge);
  s.render.width = 768;  // five surfaces: three columns, two rows of 256^2 tiles
  s.render.height = 512;
  s.receivers = {wall({kEdge, 0, -kDepth / 2}, {-1, 0, 0}, 2 * kEdge, kDepth),
                 wall({-kEdge, 0, -kDepth / 2}, {1, 0, 0}, 2 * kEdge, kDepth),
                 wall({0, kEdge, -kDepth / 2}, {0, -1, 0}, 2 * kEdge, kDepth),
                 wall({0, -kEdge, -kDepth / 2}, {0, 1, 0}, 2 * kEdge, kDepth)};
  const HdrImage img = render(s, shared(grid_mesh(flat_face(kHalf), 129, 129)));

  const double sin_t = std::sin(theta) / kWater, tan_t = sin_t / std::sqrt(1 - sin_t * sin_t);
  const double lit = transmittance(std::cos(theta), kWater) * std::cos(theta);
  const double shadow = -kHalf + kDepth * tan_t, margin = 2 * 2 * kEdge / 256;
  const Region floor = region(img, s, 0, [&](glm::dvec2 p) {
    return p.x > shadow + margin && p.x < kEdge - margin && std::abs(p.y) < kHalf - margin;
  });
  const Region dark = region(img, s, 0, [&](glm::dvec2 p) { return p.x < shadow - margin; });
  // The sunlit wall, seen from the water: right is -y, up is +z.
  const Region sunlit = region(img, s, 1, [&](glm::dvec2 p) {
    return std::abs(p.x) < kHalf - margin && std::abs(p.y) < kDepth / 2 - margin;
  });
  std::printf("floor %.5f (T cos = %.5f, spread %.1e), shadow %.2e; wall %.5f (T cos tan t = %.5f, spread %.1e)\n",
              floor.mean, lit, floor.worst, dark.mean, sunlit.mean, lit * tan_t, sunlit.worst);
  EXPECT_NEAR(floor.mean, lit, 0.005 * lit);
  EXPECT_LT(floor.worst, 1e-3);
  EXPECT_GT(dark.pixels, 1000);
  EXPECT_EQ(dark.mean, 0.0);
  EXPECT_NEAR(sunlit.mean, lit * tan_t, 0.005 * lit * tan_t);
  EXPECT_LT(sunlit.worst, 1e-3);

  // Every watt the water let through lands on the floor or the sunlit wall.
  const double entered = lit * 4 * kHalf * kHalf;
  const double on_floor = tile_flux(img, s, 0), on_wall = tile_flux(img, s, 1);
  std::printf("landed: floor %.5f + wall %.5f of %.5f; other walls %.2e, %.2e, %.2e\n", on_floor, on_wall, entered,
              tile_flux(img, s, 2), tile_flux(img, s, 3), tile_flux(img, s, 4));
  EXPECT_NEAR(on_floor + on_wall, entered, 1e-4 * entered);
  // The strip of water whose light reaches the wall above the floor, to
  // within the one column of cells whose triangles straddle the corner
  // (each landed corner takes a third, docs/physics.md §13).
  const double cell = 2 * kHalf / 128;
  EXPECT_NEAR(on_wall, lit * 2 * kHalf * (kDepth * tan_t - (kEdge - kHalf)), lit * 2 * kHalf * cell);
  // Nothing, but for the running sums' rounding (1e-16 of what a row crossed).
  for (std::size_t i = 2; i < 5; ++i) EXPECT_LT(tile_flux(img, s, i), 1e-12 * entered) << "wall " << i;
  EXPECT_EQ(engine_->stats().dropped, 0u);
}
