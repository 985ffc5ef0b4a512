// SPDX-License-Identifier: LGPL-2.1-or-later
// Scenes at the edges of what the scene format allows, each held to a result
// worked out by hand rather than to the engine's own bookkeeping: the
// largest index's Fresnel loss, a slab a micrometre and a hundred metres
// wide (in energy and in the report's area ratio), two receivers that cross each other, and a plate of glass seen
// edge-on by the light.
#include "gl_test_support.hpp"

#include <cstdio>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

// The mean of the pixels whose centres lie within `half` of the screen's
// centre, and the largest value of those farther than `outside` from it.
struct Shadow {
  double inside_min = 1e300, inside_max = -1e300, outside_max = 0;
};

Shadow read_shadow(const HdrImage& img, const ScreenParams& screen, double half, double outside) {
  Shadow s;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 at = pixel_centre(screen, img.width, img.height, x, y);
      const double v = img.at(x, y);
      if (std::abs(at.x) < half && std::abs(at.y) < half) {
        s.inside_min = std::min(s.inside_min, v);
        s.inside_max = std::max(s.inside_max, v);
      } else if (std::abs(at.x) > outside || std::abs(at.y) > outside) {
        s.outside_max = std::max(s.outside_max, v);
      }
    }
  return s;
}

// A height field that is a plane z = c: a face of a plate.
HeightField plane_at(double c, double half) {
  return {[c](double, double) { return c; }, [](double, double) { return glm::dvec2(0.0); }, half, half};
}

}  // namespace

class Extremes : public GlTest {
 protected:
  // No light lands, on the GL's set-up and the CPU's alike, and every one
  // of the 16 x 16 grid's triangles is counted as dropped.
  void expect_nothing_lands(const Scene& s, const std::shared_ptr<const Mesh>& mesh) {
    for (const TriangleSetup setup : {TriangleSetup::gpu, TriangleSetup::cpu}) {
      SCOPED_TRACE(setup == TriangleSetup::gpu ? "on the GL" : "on the CPU");
      engine_->set_triangle_setup(setup);
      const HdrImage img = render(s, mesh);
      ASSERT_TRUE(all_finite(img));
      EXPECT_EQ(total_flux(img, s.screen), 0.0);
      EXPECT_EQ(engine_->stats().drawn, 0u);
      EXPECT_EQ(engine_->stats().dropped, 2u * 16 * 16);
    }
  }
};

TEST_F(Extremes, TheLargestIndexPassesFresnelsShareOfTheLight) {
  // n = 10, the largest the scene format allows, at normal incidence:
  // R = ((n - 1) / (n + 1))^2 = (9 / 11)^2 at each face, so a slab passes
  // (1 - R)^2 = (40 / 121)^2 = 0.109282...; every pixel of its shadow reads it.
  Scene s = straight_down_scene(3.0, 50.0, 25.6, 256);
  s.render.fresnel = true;
  s.object.ior = 10.0;
  const double t = (40.0 / 121) * (40.0 / 121);
  const HdrImage img = render(s, shared(grid_mesh(flat_face(10.0), 64, 64)));
  ASSERT_TRUE(all_finite(img));
  const Shadow shadow = read_shadow(img, s.screen, 9.9, 10.1);
  EXPECT_NEAR(shadow.inside_min, t, 1e-5);
  EXPECT_NEAR(shadow.inside_max, t, 1e-5);
  EXPECT_EQ(shadow.outside_max, 0.0);
  EXPECT_NEAR(total_flux(img, s.screen), 400 * t, 1e-3 * 400 * t);
}

TEST_F(Extremes, ASlabReadsTheSameFromAMicrometreToAHundredMetres) {
  // Units are free (docs/scene-format.md): the flat slab's shadow reads
  // 0.96^2 (Fresnel, n = 1.5) whatever its size, under light tilted 30
  // degrees about x onto a screen across the beam, and the flux is its
  // face across the beam times 0.9216 there too: no tolerance in the
  // method may be an absolute length.
  for (const double half : {5e-7, 5e4}) {
    const double tilt = std::numbers::pi / 6;
    Scene s = straight_down_scene(0.1 * half, 5 * half, 2.4 * half, 240);
    s.render.fresnel = true;
    s.light.direction = {0, -std::sin(tilt), -std::cos(tilt)};
    s.screen.normal = -s.light.direction;
    s.screen.center = 5 * half * s.light.direction;
    s.screen.up = {0, std::cos(tilt), -std::sin(tilt)};
    const HdrImage img = render(s, shared(grid_mesh(flat_face(half), 48, 48)));
    ASSERT_TRUE(all_finite(img)) << half;
    // Across the beam the square's shadow is 2 half wide and 2 half cos(tilt)
    // high; Fresnel at 30 degrees in and 19.47 out, written out here.
    const double cos_t = std::sqrt(1 - 0.25 / 2.25), n = 1.5, cos_i = std::cos(tilt);
    const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (cos_t - n * cos_i) / (cos_t + n * cos_i);
    const double face = 1 - (rs * rs + rp * rp) / 2, through = face * face;  // the same angles on the way out
    const double flux = total_flux(img, s.screen), area = 4 * half * half * cos_i;
    EXPECT_NEAR(flux / area, through, 1e-3 * through) << "half width " << half;
    // The middle of the shadow, 0.6 half from its top and bottom edges.
    const Shadow middle = read_shadow(img, s.screen, 0.25 * half, 1.05 * half);
    EXPECT_NEAR(middle.inside_min, through, 1e-4) << "half width " << half;
    EXPECT_NEAR(middle.inside_max, through, 1e-4) << "half width " << half;
    EXPECT_LT(middle.outside_max, 1e-9) << "half width " << half;  // beside the shadow: rounding at most
  }
}

TEST_F(Extremes, TheReportsAreaRatioIsOneForAParallelBeamAtAnySize) {
  // "report" divides the triangle's area on the screen by its area on a
  // virtual plane behind it: a parallel beam straight through a flat slab
  // keeps its triangles' areas, so the ratio reads 1 whatever the units.
  for (const double half : {5e-7, 5e4})
    for (const TriangleSetup setup : {TriangleSetup::gpu, TriangleSetup::cpu}) {
      SCOPED_TRACE(setup == TriangleSetup::gpu ? "on the GL" : "on the CPU");
      Scene s = straight_down_scene(0.1 * half, 5 * half, 2.4 * half, 120);
      s.render.intensity = IntensityMode::report;
      s.render.report_plane_distance = half;
      engine_->set_triangle_setup(setup);
      const HdrImage img = render(s, shared(grid_mesh(flat_face(half), 32, 32)));
      ASSERT_TRUE(all_finite(img)) << half;
      const Shadow shadow = read_shadow(img, s.screen, 0.95 * half, 1.05 * half);
      EXPECT_NEAR(shadow.inside_min, 1.0, 1e-3) << "half width " << half;
      EXPECT_NEAR(shadow.inside_max, 1.0, 1e-3) << "half width " << half;
    }
}

TEST_F(Extremes, TwoReceiversThatCrossEachOtherShareTheLightAtTheirCrossing) {
  // Two planes tilted 30 degrees either way cross in a line under the
  // middle of the slab: light straight down meets the higher one first, so
  // each takes the half of the slab above it, 200 mm^2, at cos(30) by
  // Lambert's law. The column of triangles whose corners part at the
  // crossing (0.3125 x 20 mm^2) is all that may go to either.
  Scene s = straight_down_scene(1, 50, 10, 256);
  s.screen.center = {0, 300, -50};  // parked where no light goes
  const double a = std::numbers::pi / 6;
  s.receivers = {rectangle({0, 0, -30}, {std::sin(a), 0, std::cos(a)}, {0, 1, 0}, 30, 30),
                 rectangle({0, 0, -30}, {-std::sin(a), 0, std::cos(a)}, {0, 1, 0}, 30, 30)};
  const HdrImage img = render(s, fine_slab());
  ASSERT_TRUE(all_finite(img));
  const auto tiles = atlas_layout(img.width, img.height, 3);
  const double pixel = (30.0 / tiles[1].width) * (30.0 / tiles[1].height);
  const double left = tile_sum(img, tiles[1]) * pixel, right = tile_sum(img, tiles[2]) * pixel;
  EXPECT_EQ(tile_sum(img, tiles[0]), 0.0);
  EXPECT_NEAR(left + right, 400.0, 0.04);
  EXPECT_NEAR(left, 200.0, 6.25);
  EXPECT_NEAR(right, 200.0, 6.25);
  // Each lit half in its own tile: the slab's x = -5 lands on the first at
  // 5 / cos(30) to the left of its centre (its right is up x normal), the
  // slab's x = +5 on the second as far to its right.
  for (const int i : {1, 2}) {
    const AtlasTile& t = tiles[static_cast<std::size_t>(i)];
    const double local = (i == 1 ? -5 : 5) / std::cos(a);
    const int x = t.x + static_cast<int>((local + 15) / 30 * t.width), y = t.y + t.height / 2;
    EXPECT_NEAR(img.at(x, y), std::cos(a), 1e-3) << "receiver " << i - 1;
  }
}

TEST_F(Extremes, APlateEdgeOnToTheLightPassesWhatFallsOnItsEdge) {
  // A 10 x 10 x 2 mm plate (object.shape "solid"), light along x: parallel
  // to its large faces, it enters the side wall at x = -5 and leaves the one
  // at x = +5, both at normal incidence, two interfaces. Fresnel off, the
  // screen across the beam gets the wall's 10 x 2 mm^2 at irradiance 1; the
  // large faces, met only at grazing along the wall's edges, take none.
  Scene s = straight_down_scene(0, 40, 16, 256);
  s.object.flat_face_offset.reset();
  s.object.shape = Shape::solid;
  s.render.light_grid = 256;
  s.light.direction = {1, 0, 0};
  s.screen.center = {40, 0, 0};
  s.screen.normal = {-1, 0, 0};
  s.screen.up = {0, 0, 1};
  const HdrImage img = render(s, shared(closed_body(plane_at(1, 5), plane_at(-1, 5), 17)));
  ASSERT_TRUE(all_finite(img));
  const double flux = total_flux(img, s.screen);
  std::printf("edge-on plate: %.5f of the wall's 20 mm^2\n", flux / 20);
  // The strips one grid cell wide along the wall's edges (each 0.4% of it here) are sampled: measured 7e-5 over.
  EXPECT_NEAR(flux, 20.0, 2e-3 * 20);
  EXPECT_LE(flux, 20.0 * (1 + 1e-3));
  // The middle of the wall's image, 1 mm high (the plate's 2 mm, 0.5 mm in).
  double low = 1e300, high = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 at = pixel_centre(s.screen, img.width, img.height, x, y);
      const double v = img.at(x, y);
      if (std::abs(at.x) < 4.5 && std::abs(at.y) < 0.5) {
        low = std::min(low, v);
        high = std::max(high, v);
      } else if (std::abs(at.x) > 5.2 || std::abs(at.y) > 1.2) {
        EXPECT_LT(v, 1e-9) << "light beside the wall's image at " << at.x << ", " << at.y;
      }
    }
  EXPECT_NEAR(low, 1.0, 1e-3);
  EXPECT_NEAR(high, 1.0, 1e-3);
}

TEST_F(Extremes, LightThatCannotMeetTheCausticFaceLandsNothing) {
  // A face tilted 70 degrees (z = -tan(70) x, descending toward +x) under a
  // flat face at z = 3, glass of n = 1.0001 (at 1.5 the rays below would
  // reflect totally at the face anyway). Light 45 degrees from overhead
  // toward +x goes on inside at 45 degrees: along it z + tan(70) x grows by
  // tan(70) sin(45) - cos(45) = 1.24 a unit, so the light inside only draws
  // away from the face and none of it leaves through it. The same face with
  // the flat face toward the screen and light from below toward -x: there
  // z + tan(70) x falls along the light, which would meet the face only
  // from within the glass, having entered elsewhere (by the slab's side,
  // which is not part of it).
  const double apex = -70 * std::numbers::pi / 180, a = std::numbers::pi / 4;
  const auto face = shared(grid_mesh(wedge(apex, 1.0, 1.0), 17, 17));
  for (const bool flat_first : {true, false}) {
    SCOPED_TRACE(flat_first ? "flat face first" : "caustic face first");
    Scene s = straight_down_scene(3.0, 60.0, 400.0, 128);
    s.object.ior = 1.0001;
    s.light.direction = flat_first ? glm::dvec3(std::sin(a), 0, -std::cos(a)) : glm::dvec3(-std::sin(a), 0, std::cos(a));
    if (!flat_first) {  // the screen above, facing down
      s.screen.center = {0, 0, 60};
      s.screen.normal = {0, 0, -1};
    }
    expect_nothing_lands(s, face);
    EXPECT_EQ(summarize_flux(s, *face, place_object(s.object, *face)).valid_triangles, 0u);
  }
}

TEST(ExtremesShading, TheFaceShadesItselfOnlyPastNinetyDegreesLessTheLightsAngle) {
  // The 70-degree face above under light tilted toward +x by theta (inside
  // glass of n = 1.0001: the same angle to 1e-4): along the light z +
  // tan(70) x changes by tan(70) sin(theta) - cos(theta) a unit, which is
  // above 0, the light drawing away from the face that it can then reach
  // only from behind, exactly when theta > 90 - 70 = 20 degrees. Every
  // vertex of the plane is alike: the share is 0 below 20 and 1 above.
  const double apex = -70 * std::numbers::pi / 180;
  const Mesh face = grid_mesh(wedge(apex, 1.0, 1.0), 17, 17);
  Scene s = straight_down_scene(3.0, 60.0, 400.0, 128);
  s.object.ior = 1.0001;
  const Placement placed = place_object(s.object, face);
  for (const double degrees : {0.0, 15.0, 19.0, 21.0, 25.0, 45.0}) {
    SCOPED_TRACE(degrees);
    const double theta = degrees * std::numbers::pi / 180;
    s.light.direction = glm::dvec3(std::sin(theta), 0, -std::cos(theta));
    EXPECT_EQ(self_shaded_share(s, placed, face), degrees > 20 ? 1.0 : 0.0);
  }
  // The rule covers slabs only: a mirror reflects from either side.
  s.object.material = Material::reflective;
  EXPECT_EQ(self_shaded_share(s, placed, face), 0.0);
}

TEST_F(Extremes, ARayAlmostInTheScreensPlaneIsDroppedByBothSetUps) {
  // Light 5e-7 from the screen's plane through glass of index 1 (the rays
  // go on undeviated): below the 1e-6 at which a ray counts as grazing the
  // screen (docs/physics.md §4), so no vertex lands and every triangle is
  // dropped, counted alike on the GL and the CPU, as the CPU model says.
  Scene s = straight_down_scene(1.0, 50.0, 40.0, 64);
  s.object.ior = 1.0;
  s.light.direction = glm::normalize(glm::dvec3(1, 0, -5e-7));
  const auto slab = shared(grid_mesh(flat_face(10.0), 17, 17));
  EXPECT_EQ(summarize_flux(s, *slab, place_object(s.object, *slab)).valid_triangles, 0u);
  expect_nothing_lands(s, slab);
}

TEST_F(Extremes, APointLightBesideASolidLevelWithItLightsIt) {
  // A solid has no flat face, so no slab a light beside it could lie in: a
  // 10 x 10 x 2 mm plate of index 1 (no interface, Fresnel off), the light
  // 50 mm off along x, level with it, sees only its 10 x 2 mm side wall 45 mm
  // away. The light through it is E0 r_ref^2 times the wall's solid angle,
  // 4 asin(ab / sqrt((a^2 + 4d^2)(b^2 + 4d^2))), r_ref = 50 mm to the centre.
  Scene s = straight_down_scene(0, 40, 60, 256);
  s.object.flat_face_offset.reset();
  s.object.shape = Shape::solid;
  s.object.ior = 1.0;
  s.render.light_grid = 256;
  s.light.type = LightType::point;
  s.light.position = {50, 0, 0};
  s.screen.center = {-40, 0, 0};
  s.screen.normal = {1, 0, 0};
  s.screen.up = {0, 0, 1};
  const auto plate = shared(closed_body(plane_at(1, 5), plane_at(-1, 5), 17));
  const double a = 10, b = 2, d = 45;
  const double omega = 4 * std::asin(a * b / std::sqrt((a * a + 4 * d * d) * (b * b + 4 * d * d)));
  const HdrImage img = render(s, plate);
  ASSERT_TRUE(all_finite(img));
  EXPECT_NEAR(total_flux(img, s.screen), 2500 * omega, 2e-3 * 2500 * omega);
  // Within the object's box the light has no outside to shine from.
  s.light.position = {0, 0, 0};
  try {
    engine_->set_scene(s, plate);
    ADD_FAILURE() << "a light inside the solid was taken";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "light.position") << e.what();
  }
}
