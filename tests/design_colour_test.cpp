// SPDX-License-Identifier: LGPL-2.1-or-later
// Colour designs (design_colour.hpp) against their target picture: one
// face shaped for the brightest channel and tinted per vertex must throw
// each region of a colour picture in that region's colour, with the light
// of each channel where the picture has it. The renders go through the
// engine; the colours are read with the standard's own matrix.
#include "gl_test_support.hpp"

#include "caustic/design.hpp"
#include "caustic/design_colour.hpp"

#include <cmath>
#include <cstdio>

using namespace caustic;
using namespace caustic::design;
using namespace caustic::testing;

namespace {

// CIE 1931 (x, y) of linear sRGB by the IEC 61966-2-1 matrix.
glm::dvec2 xy(const glm::dvec3& c) {
  const double x = 0.4124 * c.r + 0.3576 * c.g + 0.1805 * c.b;
  const double y = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  const double z = 0.0193 * c.r + 0.1192 * c.g + 0.9505 * c.b;
  return glm::dvec2(x, y) / (x + y + z);
}

// Quadrants in four colours (top-left red, top-right green, bottom-left
// blue, bottom-right warm white) under a smooth brightness.
const glm::dvec3 kQuadrant[4] = {{1.0, 0.15, 0.1}, {0.1, 1.0, 0.2}, {0.15, 0.2, 1.0}, {1.0, 0.9, 0.8}};

int quadrant(double u, double v) { return (u < 0.5 ? 0 : 1) + (v < 0.5 ? 2 : 0); }

RgbHdrImage quadrants(int n) {
  RgbHdrImage img{n, n, std::vector<float>(3 * std::size_t(n) * n)};
  for (int row = 0; row < n; ++row)
    for (int i = 0; i < n; ++i) {
      const double u = (i + 0.5) / n, v = 1 - (row + 0.5) / n;
      const double brightness = 0.5 + 0.5 * std::exp(-((u - 0.4) * (u - 0.4) + (v - 0.6) * (v - 0.6)) / 0.08);
      for (int k = 0; k < 3; ++k)
        img.pixels[3 * (std::size_t(row) * n + i) + k] = static_cast<float>(brightness * kQuadrant[quadrant(u, v)][k]);
    }
  return img;
}

}  // namespace

class ColourDesign : public GlTest {};

TEST_F(ColourDesign, EachRegionOfTheFaceThrowsItsColour) {
  const int n = 64;
  const RgbHdrImage target = quadrants(n);
  DesignOptions o;
  o.resolution = n;
  Design d = design_face(brightest_channel(target), o);
  tint_face(d, target);
  ASSERT_EQ(d.face.colours.size(), d.face.positions.size());
  const ColourVerification v = verify_colour_with_engine(d, target);
  std::printf("quadrants: relative L1 R %.2f%%, G %.2f%%, B %.2f%%; chromaticity error %.4f; brightest channel L1 %.2f%%\n",
              100 * v.relative_l1[0], 100 * v.relative_l1[1], 100 * v.relative_l1[2], v.chromaticity_error,
              100 * v.brightest.relative_l1);
  // Each quadrant's light, four cells in from its edges, against the picture's colour.
  for (int q = 0; q < 4; ++q) {
    glm::dvec3 sum(0.0);
    for (int row = 0; row < n; ++row)
      for (int i = 0; i < n; ++i) {
        const int x = i % (n / 2), y = row % (n / 2);
        if (x < 4 || x >= n / 2 - 4 || y < 4 || y >= n / 2 - 4) continue;
        if (quadrant((i + 0.5) / n, 1 - (row + 0.5) / n) != q) continue;
        const float* p = &v.render.pixels[3 * (std::size_t(row) * n + i)];
        sum += glm::dvec3(p[0], p[1], p[2]);
      }
    const glm::dvec2 got = xy(sum), want = xy(kQuadrant[q]);
    EXPECT_NEAR(got.x, want.x, 0.005) << "quadrant " << q;
    EXPECT_NEAR(got.y, want.y, 0.005) << "quadrant " << q;
  }
  for (int k = 0; k < 3; ++k) EXPECT_LT(v.relative_l1[k], 0.05) << "channel " << k;
  EXPECT_LT(v.brightest.relative_l1, 0.02);
  EXPECT_LT(v.chromaticity_error, 0.01);
}

TEST(ColourDesignTint, BlackCellsPassWhiteAndColoursKeepTheirBrightestChannelAtOne) {
  const int n = 16;
  RgbHdrImage target{n, n, std::vector<float>(3 * n * n, 0.0f)};
  for (int i = 0; i < n * n / 2; ++i) target.pixels[3 * i] = 0.5f, target.pixels[3 * i + 2] = 0.25f;  // top half purple
  const Image shape = brightest_channel(target);
  EXPECT_FLOAT_EQ(shape.pixels[0], 0.5f);
  EXPECT_FLOAT_EQ(shape.pixels.back(), 0.0f);
  DesignOptions o;
  o.resolution = n;
  Design d = design_face(shape, o);
  tint_face(d, target);
  int purple = 0, white = 0;
  for (const auto& c : d.face.colours) {
    if (c == glm::vec3(1.0f)) ++white;
    else if (std::abs(c.r - 1.0f) < 1e-6f && c.g == 0.0f && std::abs(c.b - 0.5f) < 1e-6f) ++purple;
    else ADD_FAILURE() << "tint " << c.r << " " << c.g << " " << c.b;
  }
  EXPECT_GT(purple, 0);
  EXPECT_GT(white, 0);
}
