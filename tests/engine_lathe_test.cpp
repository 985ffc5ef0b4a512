// SPDX-License-Identifier: LGPL-2.1-or-later
// A lathe among the receivers: a cylinder lying under a flat slab, its
// light drawn in its (u, v) atlas. Oracles: Lambert's cosine law facet by
// facet, the flux it intercepts (its silhouette times E0) and the floor's
// share (the rest, its shadow dark), the seam cutting the atlas open; the
// photon reference agrees.
#include "gl_test_support.hpp"
#include "reference_l1.hpp"

#include "caustic/receivers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

constexpr double kRadius = 8, kLength = 16;
constexpr int kSegments = 32;

// A cylinder along y, its axis 30 mm below the slab, its seam (u = 0) on
// top facing the light.
Scene cylinder_scene(int pixels) {
  ScreenParams c;
  c.center = {0, 0, -30};
  c.up = {0, 1, 0};
  c.normal = {0, 0, 1};
  c.width = c.height = 1;
  c.lathe = Lathe{{{kRadius, -kLength / 2}, {kRadius, kLength / 2}}, kSegments, nullptr};
  c.lathe->mesh = std::make_shared<const ReceiverMesh>(
      make_lathe(c.lathe->profile, kSegments, c.center, c.normal, c.up));
  return over_a_floor(pixels, c);
}

// World area per (u, v) area on every facet: a facet is 2 R sin(pi / n) by
// the length, 1 / n of the atlas across.
double facet_stretch() { return 2 * kRadius * std::sin(std::numbers::pi / kSegments) * kLength * kSegments; }

}  // namespace

class EngineLathe : public GlTest {};

TEST_F(EngineLathe, EachFacetFollowsTheCosineLawAndTheFluxAddsUp) {
  const Scene s = cylinder_scene(512);
  const HdrImage img = render(s, fine_slab());
  EXPECT_TRUE(engine_->stats().cpu_setup);  // a lathe lands on the CPU whatever the renderer
  const auto tiles = atlas_layout(512, 512, 3);
  const AtlasTile t = tiles[1];
  const int per_facet = t.width / kSegments;
  const int row = t.y + t.height / 2;
  for (int k = 0; k < kSegments; ++k) {
    // Facet k's normal turns 2 pi (k + 1/2) / n from the light; its middle two columns.
    const double cosine = std::cos(2 * std::numbers::pi * (k + 0.5) / kSegments);
    const int x = t.x + k * per_facet + per_facet / 2 - 1;
    const double e = 0.5 * (img.pixels[static_cast<std::size_t>(row) * img.width + x] +
                            img.pixels[static_cast<std::size_t>(row) * img.width + x + 1]);
    // A facet narrower across the beam than 4 ray cells (1.25 mm) gets
    // too few whole triangles for its middle to be its mean.
    const double across = kRadius * std::abs(std::sin(2 * std::numbers::pi * (k + 1) / kSegments) -
                                             std::sin(2 * std::numbers::pi * k / kSegments));
    if (cosine > 0 && across >= 1.25) {
      EXPECT_NEAR(e, cosine, 0.01 * cosine) << "facet " << k;
    }
    if (cosine < 0) {
      EXPECT_NEAR(e, 0.0, 1e-12) << "facet " << k << " faces away";
    }
  }
  // Its silhouette, 2 R x the length, catches E0 = 1 over it: to within
  // the column of ray cells along its outline that parts with the floor.
  const double uv_pixel = 1.0 / (double(t.width) * t.height);
  const double on_lathe = tile_sum(img, t) * uv_pixel * facet_stretch();
  EXPECT_NEAR(on_lathe, 2 * kRadius * kLength, 0.3125 * 4 * kLength);
  const AtlasTile f = tiles[2];
  const double on_floor = tile_sum(img, f) * (40.0 / f.width) * (40.0 / f.height);
  EXPECT_NEAR((on_lathe + on_floor) / 400.0, 1.0, 1e-4);  // the slab's 20 x 20 mm, every ray somewhere
  // Straight under the cylinder the floor lies in its shade: nothing but
  // the rounding of the pieces' edges, walked apart, along its rows.
  EXPECT_LT(img.pixels[static_cast<std::size_t>(f.y + f.height / 2) * img.width + f.x + f.width / 2], 1e-12f);
}

TEST_F(EngineLathe, ItsShadowsOutlineIsWhereTheLightGrazesIt) {
  // Straight down, the cylinder shades the floor's square |x|, |y| < R
  // (its length is 2 R) inside the slab's 20 x 20 mm of E0 = 1. The ray
  // cells along the outline part between cylinder and floor; sampled finer
  // than their corners, the outline lies where it should to within the
  // samples' spacing (a quarter of a cell), not a cell's: the floor's light
  // against the exact picture, pixel by pixel.
  const Scene s = cylinder_scene(512);
  const HdrImage img = render(s, fine_slab());
  const AtlasTile f = atlas_layout(512, 512, 3)[2];
  const double pixel = 40.0 / f.width;
  ASSERT_EQ(f.width, f.height);
  // The length of [lo, hi] inside [-half, half].
  const auto inside = [](double lo, double hi, double half) { return std::max(0.0, std::min(hi, half) - std::max(lo, -half)); };
  double differ = 0, lit = 0;
  for (int j = 0; j < f.height; ++j)
    for (int i = 0; i < f.width; ++i) {
      const double x0 = -20 + i * pixel, y0 = -20 + j * pixel;
      const double exact = (inside(x0, x0 + pixel, 10) * inside(y0, y0 + pixel, 10) -
                            inside(x0, x0 + pixel, kRadius) * inside(y0, y0 + pixel, kLength / 2)) /
                           (pixel * pixel);
      const double e = img.pixels[static_cast<std::size_t>(f.y + j) * img.width + f.x + i];
      differ += std::abs(e - exact) * pixel * pixel;
      lit += exact * pixel * pixel;
    }
  EXPECT_NEAR(lit, 400 - 4 * kRadius * kRadius, 1e-9);
  // The outline is 4 x 16 mm long and a cell 0.3125 mm wide: with a third
  // of each parted cell's flux at its corners (caustic.geom's way) 9.7% of
  // the floor's light lay in the wrong pixels; sampled, 0.35%.
  EXPECT_LT(differ / lit, 0.01);
}

TEST_F(EngineLathe, AlongItsAxisEveryLitColumnIsEven) {
  // The slab and the straight-down beam are the same all along the
  // cylinder's axis, so each column of its atlas (one u) is lit the same in
  // every row. The last lit facets (6 and 7 of 32, and their mirror images)
  // are reached mostly by ray cells that part with the floor: cut into
  // pieces that are spread whole where their corners land together, they
  // stay even; 16 points each, as a cell was sampled before, they were
  // dots, rows lit and rows dark. Only the column at the outline and the
  // one at the seam, where the smallest pieces still part and leave points,
  // are left out.
  const Scene s = cylinder_scene(512);
  const HdrImage img = render(s, fine_slab());
  const AtlasTile t = atlas_layout(512, 512, 3)[1];
  int lit = 0;
  for (int i = 0; i < t.width; ++i) {
    const double u = (i + 0.5) / t.width;
    const bool parting = std::abs(u - 0.25) < 1.0 / t.width || std::abs(u - 0.75) < 1.0 / t.width ||
                         u < 1.0 / t.width || u > 1 - 1.0 / t.width;
    if (parting) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (int y = t.y + t.height / 4; y < t.y + 3 * t.height / 4; ++y) {  // clear of the ends
      const double e = img.pixels[static_cast<std::size_t>(y) * img.width + t.x + i];
      lo = std::min(lo, e), hi = std::max(hi, e);
    }
    if (hi < 1e-12) continue;  // in the shade
    ++lit;
    EXPECT_LT(hi - lo, 0.01 * hi) << "column " << i << " (u = " << u << ") from " << lo << " to " << hi;
  }
  // The upper half of the cylinder faces the light: 16 of its 32 facets.
  EXPECT_GE(lit, 0.4 * t.width);
}

TEST_F(EngineLathe, TheSeamCutsTheAtlasOpen) {
  // The seam runs along the top, in the middle of the light: rays on its
  // two sides land at u near 0 and near 1. Joined into one triangle of the
  // atlas they would smear light across the whole tile; the back half of
  // the cylinder, u from 0.3 to 0.7, is in the dark.
  const Scene s = cylinder_scene(256);
  const HdrImage img = render(s, fine_slab());
  const AtlasTile t = atlas_layout(256, 256, 3)[1];
  double back = 0, front = 0;
  for (int y = t.y; y < t.y + t.height; ++y)
    for (int x = t.x; x < t.x + t.width; ++x) {
      const double u = (x - t.x + 0.5) / t.width;
      (u > 0.3 && u < 0.7 ? back : front) += img.pixels[static_cast<std::size_t>(y) * img.width + x];
    }
  EXPECT_GT(front, 0.0);
  EXPECT_LT(back, 1e-9 * front);  // the raster's sums of signed areas: zero to rounding
}

TEST_F(EngineLathe, TheReferenceTracerAgrees) {
  // The rays 0.04 mm apart, a tenth of the tile's pixels: what differs is
  // the column of ray cells across the seam and along the outline, whose
  // corners land apart (cut into pieces, the smallest that part points), and the two
  // grazing facets a cell or two wide, where a triangle of the atlas
  // straddles the crease between facets. Both shrink with the spacing.
  Scene s = cylinder_scene(128);
  s.render.fresnel = true;
  // The axis off the rays' grid: a ray exactly on the seam would land on
  // one side of it, and every one on the seam on the same side.
  s.receivers[0].center.x = 0.0123;
  s.receivers[0].lathe->mesh = std::make_shared<const ReceiverMesh>(make_lathe(
      s.receivers[0].lathe->profile, kSegments, s.receivers[0].center, s.receivers[0].normal, s.receivers[0].up));
  const auto fine = shared(grid_mesh(flat_face(10), 513, 513));
  const HdrImage engine = render(s, fine);
  EXPECT_LT(reference_l1(s, *fine, engine, "cylinder and floor"), 0.01);
}
