// SPDX-License-Identifier: LGPL-2.1-or-later
// Several receivers: the light lands on the first surface it meets, each
// surface's irradiance in its own atlas tile. Oracles: Lambert's cosine law
// on a tilted plane, flux conserved over a floor and a wall, nothing on a
// surface another one shades; the photon reference agrees.
#include "gl_test_support.hpp"
#include "reference_l1.hpp"

#include "caustic/receivers.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

// A 20 x 20 mm flat slab, its flat face at z = 1 (the light's side).
std::shared_ptr<const Mesh> slab() {
  static const auto mesh = shared(grid_mesh(flat_face(10), 33, 33));
  return mesh;
}

// Straight down, Fresnel off; the screen parked where no light goes.
Scene base_scene(int pixels) {
  Scene s = straight_down_scene(1, 50, 10, pixels);
  s.screen.center = {0, 300, -50};
  return s;
}

// Sum of irradiance times pixel area over one surface's tile.
double tile_flux(const HdrImage& img, const Scene& s, std::size_t surface) {
  const auto tiles = atlas_layout(img.width, img.height, 1 + s.receivers.size());
  const auto& t = tiles[surface];
  const auto surfaces = receiving_surfaces(s);
  const auto& r = surfaces[surface];
  double sum = 0;
  for (int y = t.y; y < t.y + t.height; ++y)
    for (int x = t.x; x < t.x + t.width; ++x) sum += img.pixels[static_cast<std::size_t>(y) * img.width + x];
  return sum * (r.width / t.width) * (r.height / t.height);
}

// Light (1, 0, -1) through the slab onto a floor (z = -30) and the wall at
// x = 25 it meets first: between them they catch every ray.
Scene floor_and_wall(int pixels) {
  Scene s = base_scene(pixels);
  s.light.direction = glm::normalize(glm::dvec3(1, 0, -1));
  s.receivers = {rectangle({20, 0, -30}, {0, 0, 1}, {0, 1, 0}, 10, 30),
                 rectangle({25, 0, -22.5}, {-1, 0, 0}, {0, 0, 1}, 30, 25)};
  return s;
}

}  // namespace

class EngineReceivers : public GlTest {};

TEST_F(EngineReceivers, ATiltedPlaneFollowsTheCosineLaw) {
  for (const double degrees : {0.0, 30.0, 60.0}) {
    Scene s = base_scene(256);
    const double a = degrees * std::numbers::pi / 180;
    // Tilted about y, 40 mm below; 30 x 30 mm catches the whole beam.
    s.receivers = {rectangle({0, 0, -40}, {std::sin(a), 0, std::cos(a)}, {0, 1, 0}, 40, 40)};
    const HdrImage img = render(s, slab());
    const AtlasTile t = atlas_layout(256, 256, 2)[1];
    // The middle of the lit patch: E = E0 cos(theta), Fresnel off.
    const float e = img.pixels[static_cast<std::size_t>(t.y + t.height / 2) * img.width + t.x + t.width / 2];
    EXPECT_NEAR(e, std::cos(a), 0.01 * std::cos(a)) << degrees;
    EXPECT_NEAR(tile_flux(img, s, 1), 400.0, 0.04) << degrees;  // all of it, whatever the tilt
  }
}

TEST_F(EngineReceivers, AFloorAndAWallShareTheFluxWithoutLosingAny) {
  const Scene s = floor_and_wall(512);
  const HdrImage img = render(s, slab());
  const double floor = tile_flux(img, s, 1), wall = tile_flux(img, s, 2);
  const double in = 400.0 * std::cos(std::numbers::pi / 4);  // the slab's face across the beam
  EXPECT_GT(floor, 0.2 * in);
  EXPECT_GT(wall, 0.6 * in);
  EXPECT_NEAR((floor + wall) / in, 1.0, 1e-4);
  EXPECT_EQ(tile_flux(img, s, 0), 0.0);  // the parked screen
  EXPECT_GT(engine_->stats().collapsed, 0u);  // the corner's triangles parted
}

TEST_F(EngineReceivers, ASurfaceInTheShadeOfAnotherGetsNothing) {
  Scene s = base_scene(256);
  s.receivers = {rectangle({0, 0, -20}, {0, 0, 1}, {0, 1, 0}, 30, 30),   // in front
                 rectangle({0, 0, -40}, {0, 0, 1}, {0, 1, 0}, 30, 30)};  // behind it
  const HdrImage img = render(s, slab());
  EXPECT_NEAR(tile_flux(img, s, 1), 400.0, 0.04);
  EXPECT_EQ(tile_flux(img, s, 2), 0.0);
  // Half of the front one gone: half the light reaches the back, to within
  // the column of grid cells the shadow's edge crosses (0.625 x 20 mm).
  s.receivers[0] = rectangle({-10, 0, -20}, {0, 0, 1}, {0, 1, 0}, 20, 30);
  const HdrImage half = render(s, slab());
  EXPECT_NEAR(tile_flux(half, s, 2), 200.0, 12.5);
  EXPECT_NEAR(tile_flux(half, s, 1) + tile_flux(half, s, 2), 400.0, 0.04);
}

TEST_F(EngineReceivers, TheReferenceTracerAgreesOnTheFloorAndTheWall) {
  // A finer slab: the column of grid cells at the floor's edge, whose
  // corners part between the floor and the wall, is what differs.
  Scene s = floor_and_wall(128);
  s.render.fresnel = true;
  const auto fine = shared(grid_mesh(flat_face(10), 257, 257));
  const HdrImage engine = render(s, fine);
  EXPECT_LT(reference_l1(s, *fine, engine, "floor and wall"), 0.01);
}

TEST_F(EngineReceivers, ASolidLightsThemToo) {
  // The multipass method lands its rays by the same rule: a biconvex lens
  // over a floor cut in two along its axis gives each half half the light.
  Scene s = base_scene(256);
  s.object.flat_face_offset.reset();
  s.object.shape = Shape::solid;
  s.receivers = {rectangle({-10, 0, -30}, {0, 0, 1}, {0, 1, 0}, 20, 30),
                 rectangle({10, 0, -30}, {0, 0, 1}, {0, 1, 0}, 20, 30)};
  const auto lens = shared(biconvex_lens(50, 50, 4, 5, 65));
  const HdrImage img = render(s, lens);
  const double left = tile_flux(img, s, 1), right = tile_flux(img, s, 2);
  EXPECT_NEAR((left + right) / 100.0, 1.0, 1e-3);  // the 10 x 10 mm aperture, Fresnel off
  EXPECT_NEAR(left / right, 1.0, 1e-3);
}

TEST_F(EngineReceivers, OneEdgeOnToTheLightCatchesNothingAndBreaksNothing) {
  // A wall, its plane along the light: every ray runs parallel to it.
  // Beside the slab, and touching its edge (x = 10), where the last column
  // of vertices' rays run in its plane (0 / 0 for a hit). A plane through
  // the beam would cross the object's box, which the scene refuses.
  for (double x : {12.0, 10.0}) {
    Scene s = base_scene(128);
    s.receivers = {rectangle({x, 0, -20}, {-1, 0, 0}, {0, 0, 1}, 30, 20),
                   rectangle({0, 0, -40}, {0, 0, 1}, {0, 1, 0}, 30, 30)};
    const HdrImage img = render(s, slab());
    EXPECT_TRUE(all_finite(img)) << "wall at x = " << x;
    EXPECT_EQ(tile_flux(img, s, 1), 0.0) << "wall at x = " << x;
    EXPECT_NEAR(tile_flux(img, s, 2), 400.0, 0.04) << "wall at x = " << x;
  }
}

TEST_F(EngineReceivers, TheGlowStaysOnTheSurfaceItsLightReached) {
  // The slab's square of light on a receiver, the atlas's right tile, its
  // left edge 21 px from the tile of the parked screen on the left; a glow
  // of 16 px reaches 48. The atlas lays unrelated surfaces side by side, so
  // both post-processing paths stop the glow at its tile's edges.
  Scene s = base_scene(256);
  s.receivers = {rectangle({0, 0, -20}, {0, 0, 1}, {0, 1, 0}, 30, 30)};
  s.post.bloom_threshold = 0.1;
  s.post.bloom_strength = 1.0;
  s.post.bloom_radius = 16;
  for (const TriangleSetup setup : {TriangleSetup::gpu, TriangleSetup::cpu}) {
    SCOPED_TRACE(setup == TriangleSetup::gpu ? "on the GL" : "on the CPU");
    engine_->set_triangle_setup(setup);
    const HdrImage hdr = render(s, slab());
    EXPECT_EQ(engine_->stats().cpu_post, setup == TriangleSetup::cpu);
    const Rgba8Image ldr = engine_->read_ldr();
    const auto at = [&](int x, int y) { return static_cast<int>(ldr.pixels[(static_cast<std::size_t>(y) * 256 + x) * 4]); };
    int on_screen = 0;
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 128; ++x) on_screen = std::max(on_screen, at(x, y));
    EXPECT_EQ(on_screen, 0) << "the receiver's glow reached the screen's tile";
    // Beside the square within its own tile: dark in the HDR image, lit by the glow.
    EXPECT_EQ(hdr.pixels[128 * 256 + 140], 0.0f);
    EXPECT_GT(at(140, 128), 8);
    EXPECT_GT(at(128, 128), 0);  // the tile's first column glows too
  }
}
