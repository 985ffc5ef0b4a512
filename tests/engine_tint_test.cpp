// SPDX-License-Identifier: LGPL-2.1-or-later
// A tinted face (Mesh::colours) against closed forms (docs/physics.md §11):
// under a flat slab half tinted red and half clear, the red half's light is
// the tint times the light, with the chromaticity of the tint, and the clear
// half's is the white the frame is balanced to, with or without dispersion.
#include "gl_test_support.hpp"

#include "caustic/colour.hpp"

#include <cmath>

using namespace caustic;
using namespace caustic::testing;

namespace {

// Linear sRGB (IEC 61966-2-1) to CIE 1931 chromaticity, from the standard's
// matrix: the oracle does not use the project's own conversion.
glm::dvec2 chromaticity(double r, double g, double b) {
  const double x = 0.4124 * r + 0.3576 * g + 0.1805 * b;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = 0.0193 * r + 0.1192 * g + 0.9505 * b;
  return {x / (x + y + z), y / (x + y + z)};
}

constexpr glm::vec3 kRed{1.0f, 0.2f, 0.1f};  // a red glass: most red passes, little else

// A 20 x 20 mm slab whose vertices left of x = 0 carry `tint`.
Mesh half_tinted_slab(glm::vec3 tint) {
  Mesh m = grid_mesh(flat_face(10.0), 33, 33);  // a column of vertices on x = 0
  for (const auto& p : m.positions) m.colours.push_back(p.x < -1e-6f ? tint : glm::vec3(1.0f));
  return m;
}

struct Halves {
  glm::dvec3 worst_red{0.0}, worst_clear{0.0};  // largest deviation per channel
  glm::dvec2 worst_red_xy{0.0}, worst_clear_xy{0.0};
  int red = 0, clear = 0;
  int dark = 0;  // unlit: no chromaticity to compare (0 / 0), so counted apart
};

// Compares each lit pixel at least `margin` mm from the seam with what the
// half it lies under lets through: `tint` on the left, white on the right.
Halves compare(const RgbHdrImage& img, const ScreenParams& screen, glm::dvec3 tint, double margin) {
  Halves h;
  const glm::dvec2 red_xy = chromaticity(tint.r, tint.g, tint.b), white_xy = chromaticity(1, 1, 1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 at = pixel_centre(screen, img.width, img.height, x, y);
      if (std::abs(at.x) < margin || std::abs(at.x) > 10 - margin || std::abs(at.y) > 10 - margin) continue;
      const float* p = &img.pixels[3 * (static_cast<std::size_t>(y) * img.width + x)];
      const glm::dvec3 v(p[0], p[1], p[2]);
      if (!(v.r + v.g + v.b > 0)) {
        ++h.dark;
        continue;
      }
      const bool left = at.x < 0;
      const glm::dvec3 expected = left ? tint : glm::dvec3(1.0);
      const glm::dvec2 xy = chromaticity(v.r, v.g, v.b) - (left ? red_xy : white_xy);
      auto& worst = left ? h.worst_red : h.worst_clear;
      auto& worst_xy = left ? h.worst_red_xy : h.worst_clear_xy;
      worst = glm::max(worst, glm::abs(v - expected));
      worst_xy = glm::max(worst_xy, glm::abs(xy));
      ++(left ? h.red : h.clear);
    }
  return h;
}

class Tint : public GlTest {};

}  // namespace

TEST_F(Tint, TheStandardsPrimariesAreTheOraclesOwn) {
  // The oracle's matrix reproduces the sRGB primaries and D65 white it is
  // built from (IEC 61966-2-1: R 0.64, 0.33; D65 0.3127, 0.3290).
  EXPECT_NEAR(chromaticity(1, 0, 0).x, 0.64, 1e-3);
  EXPECT_NEAR(chromaticity(1, 0, 0).y, 0.33, 1e-3);
  EXPECT_NEAR(chromaticity(1, 1, 1).x, 0.3127, 1e-3);
  EXPECT_NEAR(chromaticity(1, 1, 1).y, 0.3290, 1e-3);
}

TEST_F(Tint, ARedHalfPassesItsTintAndAClearHalfStaysWhite) {
  const auto slab = shared(half_tinted_slab(kRed));
  const Scene s = straight_down_scene(3.0, 50.0, 25.6, 128);
  const RgbHdrImage img = render_rgb(s, slab);
  EXPECT_TRUE(engine_->stats().colour);
  EXPECT_EQ(engine_->stats().wavelengths, 1);  // no glass: one pass, filtered in colour
  const Halves h = compare(img, s.screen, glm::dvec3(kRed), 1.0);
  EXPECT_GT(h.red, 3000);
  EXPECT_GT(h.clear, 3000);
  EXPECT_EQ(h.dark, 0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(h.worst_red[c], 1e-4) << "channel " << c;
    EXPECT_LT(h.worst_clear[c], 1e-4) << "channel " << c;
  }
  EXPECT_LT(std::max(h.worst_red_xy.x, h.worst_red_xy.y), 1e-3);
  EXPECT_LT(std::max(h.worst_clear_xy.x, h.worst_clear_xy.y), 1e-3);
  // The flux per channel: the tint interpolated linearly across the face
  // (Mesh::colours) integrated over its 20 mm x 20 mm: tinted left of the
  // last column of red vertices, clear right of x = 0, a ramp between.
  const double area = 25.6 * 25.6 / (128.0 * 128.0), step = 20.0 / 32;
  glm::dvec3 flux(0.0);
  for (std::size_t i = 0; i < img.pixels.size(); i += 3)
    flux += glm::dvec3(img.pixels[i], img.pixels[i + 1], img.pixels[i + 2]) * area;
  for (int c = 0; c < 3; ++c) {
    const double expected = 20.0 * (kRed[c] * (10.0 - step) + step * (kRed[c] + 1.0) / 2 + 10.0);
    EXPECT_NEAR(flux[c], expected, 1e-4 * expected) << "channel " << c;
  }
}

TEST_F(Tint, ATintFiltersEveryWavelengthOfADispersiveGlass) {
  // BK7 under a warm blackbody: the frame is white-balanced to the light,
  // so the clear half is white and the red half is the tint again.
  const auto slab = shared(half_tinted_slab(kRed));
  Scene s = straight_down_scene(3.0, 50.0, 25.6, 128);
  s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
  s.object.ior = s.object.glass->index(optics::kLineD);
  s.light.spectrum = {optics::Illuminant::blackbody, 2700};
  const RgbHdrImage img = render_rgb(s, slab);
  EXPECT_EQ(engine_->stats().wavelengths, 8);
  const Halves h = compare(img, s.screen, glm::dvec3(kRed), 1.0);
  EXPECT_GT(h.red, 3000);
  EXPECT_GT(h.clear, 3000);
  EXPECT_EQ(h.dark, 0);
  // Straight down through a flat slab every wavelength lands where it
  // entered, and a balanced frame's band weights sum to 1 in each channel:
  // the halves are the tint and white in value, not only in chromaticity.
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(h.worst_red[c], 1e-3) << "channel " << c;
    EXPECT_LT(h.worst_clear[c], 1e-3) << "channel " << c;
  }
  EXPECT_LT(std::max(h.worst_red_xy.x, h.worst_red_xy.y), 1e-3);
  EXPECT_LT(std::max(h.worst_clear_xy.x, h.worst_clear_xy.y), 1e-3);
}

TEST_F(Tint, ATrianglePassesTheMeanOfItsCornersColours) {
  // One triangle with a red, a green and a blue corner: the tint
  // interpolated linearly averages to a third of each over its area, so each
  // channel carries a third of the flux (50 mm^2 of light straight down).
  Mesh m;
  m.positions = {{-5, -5, 0}, {5, -5, 0}, {0, 5, 0}};
  m.normals.assign(3, glm::vec3(0, 0, 1));
  m.triangles = {{0, 1, 2}};
  m.colours = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Scene s = straight_down_scene(3.0, 50.0, 25.6, 128);
  const RgbHdrImage img = render_rgb(s, shared(std::move(m)));
  const double area = 25.6 * 25.6 / (128.0 * 128.0);
  glm::dvec3 flux(0.0);
  for (std::size_t i = 0; i < img.pixels.size(); i += 3)
    flux += glm::dvec3(img.pixels[i], img.pixels[i + 1], img.pixels[i + 2]) * area;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(flux[c], 50.0 / 3, 1e-4 * 50) << "channel " << c;
}

TEST_F(Tint, AClearFaceAfterATintedOneIsGreyAgain) {
  // The tint attribute of the first mesh must not leak into the next.
  render_rgb(straight_down_scene(3.0, 50.0, 25.6, 64), shared(half_tinted_slab(kRed)));
  const Scene s = straight_down_scene(3.0, 50.0, 25.6, 64);
  const HdrImage grey = render(s, shared(grid_mesh(flat_face(10.0), 33, 33)));
  EXPECT_FALSE(engine_->stats().colour);
  EXPECT_NEAR(total_flux(grey, s.screen), 400.0, 0.4);
}
