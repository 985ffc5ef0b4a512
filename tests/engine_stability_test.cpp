// SPDX-License-Identifier: LGPL-2.1-or-later
// Where the per-vertex method meets its limits (docs/physics.md ch. 6):
// each case has a defined outcome, never NaN/Inf and never a crash.
#include "gl_test_support.hpp"

#include <limits>

using namespace caustic;
using namespace caustic::testing;

class Stability : public GlTest {
 protected:
  // Renders with the screen framed around every valid hit and checks that
  // the image is finite and holds exactly the flux the CPU model expects;
  // unless `lit` is false, some light must reach the screen (a case that
  // dropped every ray would otherwise pass as "nothing, and finite").
  FrameStats render_and_balance(Scene s, const Mesh& mesh_value, unsigned zero_flux_triangles = 0, bool lit = true) {
    const auto mesh = shared(mesh_value);
    FluxSummary expected;
    if (!frame_screen(s, *mesh, &expected)) {
      EXPECT_FALSE(lit) << "no ray reaches the screen";
      const HdrImage img = render(s, mesh);
      EXPECT_TRUE(all_finite(img));
      for (float v : img.pixels) EXPECT_EQ(v, 0.0f);
      return engine_->stats();
    }
    const HdrImage img = render(s, mesh);
    EXPECT_TRUE(all_finite(img));
    EXPECT_GT(expected.valid_triangles, 0u);
    EXPECT_NEAR(total_flux(img, s.screen), expected.flux, 1e-3 * expected.flux);
    EXPECT_EQ(engine_->stats().drawn, expected.valid_triangles - zero_flux_triangles);
    return engine_->stats();
  }
};

TEST_F(Stability, TotalInternalReflectionDropsThoseTriangles) {
  Scene s = straight_down_scene(4.0, 30.0, 10.0, 256);
  s.object.ior = 3.0;  // the lens corners exceed the critical angle of 19.5 degrees
  const FrameStats st = render_and_balance(s, grid_mesh(plano_convex_lens(40.0, 10.0), 64, 64));
  EXPECT_GT(st.dropped, 0u);
  EXPECT_GT(st.drawn, 0u);
}

TEST_F(Stability, GrazingLightIsFiniteAndDim) {
  for (const double degrees : {85.0, 89.9, 89.999}) {
    Scene s = straight_down_scene(4.0, 30.0, 10.0, 128);
    const double a = glm::radians(degrees);
    s.light.direction = {std::sin(a), 0, -std::cos(a)};
    render_and_balance(s, grid_mesh(plano_convex_lens(40.0, 10.0), 48, 48));
  }
  // Light exactly parallel to the flat face enters through the caustic face,
  // bends up into the glass and leaves through the flat face, away from the
  // screen below: nothing lands, and nothing breaks.
  Scene s = straight_down_scene(4.0, 30.0, 10.0, 128);
  s.light.direction = {1, 0, 0};
  render_and_balance(s, grid_mesh(plano_convex_lens(40.0, 10.0), 48, 48), 0, false);
}

TEST_F(Stability, ScreenOnTheLightSideReceivesNothing) {
  Scene s = straight_down_scene(4.0, 30.0, 30.0, 128);
  s.screen.center = {0, 0, 50};
  s.screen.normal = {0, 0, -1};
  const HdrImage img = render(s, shared(grid_mesh(plano_convex_lens(40.0, 10.0), 32, 32)));
  EXPECT_TRUE(all_finite(img));
  for (float v : img.pixels) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(engine_->stats().drawn, 0u);
  EXPECT_EQ(engine_->stats().dropped, 2u * 31 * 31);
}

TEST_F(Stability, DegenerateTrianglesCarryNoFlux) {
  Mesh m = grid_mesh(plano_convex_lens(40.0, 10.0), 32, 32);
  const auto n = static_cast<unsigned>(m.positions.size());
  m.triangles.push_back({0, 0, 0});        // a point
  m.triangles.push_back({0, 1, 1});        // a segment
  m.positions.push_back(m.positions[5]);   // a duplicate vertex
  m.normals.push_back(m.normals[5]);
  m.triangles.push_back({5, n, 6});
  // The three zero-area triangles reach the screen but are not drawn.
  render_and_balance(straight_down_scene(4.0, 30.0, 10.0, 128), m, 3);
}

TEST_F(Stability, FoldedTrianglesAreCountedAndKept) {
  // Folds start at 1 / ((n - 1) A k^2) = 13.9 mm; at 40 mm the sheets overlap.
  Scene s = straight_down_scene(2.0, 40.0, 10.0, 256);
  const FrameStats st = render_and_balance(s, grid_mesh(sine_window(0.4, 0.6, 0.0, 1.0, 10.0), 96, 96));
  EXPECT_GT(st.folded, 1000u);
}

TEST_F(Stability, ExactFocusStaysFiniteAndKeepsItsEnergy) {
  // A point focus with a small aperture: triangles collapse to (almost) nothing.
  Scene s = straight_down_scene(4.0, 80.0, 0.5, 256);
  s.screen.center.z = -79.95;
  const auto mesh = shared(grid_mesh(plano_convex_lens(40.0, 0.5), 64, 64));
  const HdrImage img = render(s, mesh);
  ASSERT_TRUE(all_finite(img));
  FluxSummary expected = summarize_flux(s, *mesh, place_object(s.object, *mesh));
  EXPECT_NEAR(total_flux(img, s.screen), expected.flux, 1e-3 * expected.flux);
  float peak = 0;
  for (float v : img.pixels) peak = std::max(peak, v);
  EXPECT_GT(peak, 1e3f);  // concentrated, and finite
}

TEST_F(Stability, ExtremeIndicesOfRefraction) {
  for (const double ior : {1.0001, 1.0, 2.4, 4.0}) {
    Scene s = straight_down_scene(4.0, 30.0, 10.0, 128);
    s.object.ior = ior;
    render_and_balance(s, grid_mesh(plano_convex_lens(40.0, 10.0), 48, 48));
  }
}

TEST_F(Stability, PointLightAlmostOnTheFlatFace) {
  for (const PointModel model : {PointModel::exact, PointModel::approximate}) {
    Scene s = straight_down_scene(4.0, 30.0, 10.0, 128);
    s.light.type = LightType::point;
    s.light.point_model = model;
    s.light.position = {3, 1, 4.001};
    render_and_balance(s, grid_mesh(plano_convex_lens(40.0, 10.0), 48, 48));
  }
}

TEST_F(Stability, ReflectiveObjectMirrorsTheLight) {
  Scene s = straight_down_scene(4.0, 30.0, 10.0, 128);
  s.object.material = Material::reflective;
  s.light.direction = glm::normalize(glm::dvec3(0.2, 0, 1));  // from below onto the mirror face
  s.screen.center = {0, 0, -60};
  s.screen.normal = {0, 0, 1};
  const FrameStats st = render_and_balance(s, grid_mesh(plano_convex_lens(40.0, 10.0), 48, 48));
  EXPECT_GT(st.drawn, 0u);
}

TEST_F(Stability, AFlatMirrorReflectsByTheLawOfReflection) {
  // A flat 20 x 20 mm mirror lit from below at 11.3 degrees (direction
  // (0.2, 0, 1)): the law of reflection sends the beam down as (0.2, 0, -1),
  // so the screen 60 mm below the centre of the mirror gets the mirror's
  // square, moved 0.2 mm in x for every mm it falls, lit evenly at the cosine
  // of the incidence (the screen is parallel to the mirror).
  Scene s = straight_down_scene(4.0, 60.0, 40.0, 256);
  s.object.material = Material::reflective;
  s.light.direction = glm::normalize(glm::dvec3(0.2, 0, 1));
  const auto mirror = shared(grid_mesh(flat_face(10.0), 33, 33));
  const double face_z = glm::dvec3(place_object(s.object, *mirror).model * glm::dvec4(0, 0, 0, 1)).z;
  const double shift = 0.2 * (face_z - s.screen.center.z), cos_i = 1 / std::sqrt(1.04);
  s.screen.center.x = std::round(shift);  // the square whole on the screen, off its centre by the rest
  const HdrImage img = render(s, mirror);
  ASSERT_TRUE(all_finite(img));
  const double pixel = 40.0 / 256;
  double worst = 0;
  int inside = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 at =
          pixel_centre(s.screen, img.width, img.height, x, y) + glm::dvec2(s.screen.center.x - shift, 0);
      const double v = img.at(x, y);
      if (std::abs(at.x) < 10 - pixel && std::abs(at.y) < 10 - pixel) {
        worst = std::max(worst, std::abs(v - cos_i));
        ++inside;
      } else if (std::abs(at.x) > 10 + pixel || std::abs(at.y) > 10 + pixel) {
        ASSERT_EQ(v, 0.0f) << "light outside the reflected square at " << at.x << ", " << at.y;
      }
    }
  EXPECT_GT(inside, 9000);
  EXPECT_LT(worst, 1e-4 * cos_i);
  EXPECT_NEAR(total_flux(img, s.screen), 400 * cos_i, 1e-3 * 400 * cos_i);
}
