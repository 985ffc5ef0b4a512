// SPDX-License-Identifier: LGPL-2.1-or-later
// The plano-convex lens against its exact rotationally symmetric ray map
// (docs/physics.md ch. 7), traced here in 2D with scalar trigonometry so the
// oracle shares nothing with the engine.
#include "gl_test_support.hpp"
#include "lens_oracle.hpp"

#include <cmath>
#include <cstdio>

using namespace caustic;
using namespace caustic::testing;

using namespace caustic::oracle;

class PlanoConvexLens : public GlTest {};

TEST_F(PlanoConvexLens, ProfileMatchesTheExactRayMapBeforeFocus) {
  // E(rs) = sum over branches of r / (rs |d rs / d r|), over the preimages r
  // that lie inside the square aperture. Pixels within a few pixels of a
  // caustic (the focus ring, where d rs / d r = 0) or of the image of the
  // aperture's edge are left out: there a pixel's average and the value at
  // its centre legitimately differ.
  // Measured at most 0.05% on either set-up; a triangle under half a pixel
  // put whole into one pixel gives 1.3 % at 20 mm, and 5 % at 60 mm.
  const double half = 10.0;
  const auto lens = shared(grid_mesh(plano_convex_lens(kRadius, half), 256, 256));
  for (const TriangleSetup setup : {TriangleSetup::gpu, TriangleSetup::cpu}) {
    SCOPED_TRACE(setup == TriangleSetup::gpu ? "on the GL" : "on the CPU");
    engine_->set_triangle_setup(setup);
    for (const double z : {20.0, 40.0, 60.0}) {
      Scene s = straight_down_scene(4.0, z, lens_screen_size(z, half), 384);
      const HdrImage img = render(s, lens);
      ASSERT_TRUE(all_finite(img));
      const auto [l1, used] = compare_with_ray_map(img, s.screen.width, z, half);
      std::printf("%s, z = %.0f mm: relative L1 %.4f over %d pixels\n", setup == TriangleSetup::gpu ? "GL" : "CPU", z,
                  l1, used);
      EXPECT_GT(used, 10000) << "z = " << z;
      EXPECT_LT(l1, 0.005) << "relative L1 at z = " << z;
    }
  }
}

TEST_F(PlanoConvexLens, BrightestSpotAtTheFocalLength) {
  // A small aperture (f/10) keeps spherical aberration well under 1% of f;
  // the spot is brightest where the flux within a small radius peaks.
  const auto lens = shared(grid_mesh(plano_convex_lens(kRadius, 2.0), 160, 160));
  const double window = 0.6, radius = 0.01;
  double best_z = 0, best_flux = -1;
  for (double z = 0.9 * kFocal; z <= 1.1 * kFocal + 1e-9; z += 0.004 * kFocal) {
    const Scene s = straight_down_scene(4.0, z, window, 512);
    const HdrImage img = render(s, lens);
    ASSERT_TRUE(all_finite(img));
    double flux = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (glm::length(pixel_centre(s.screen, img.width, img.height, x, y)) <= radius) flux += img.at(x, y);
    if (flux > best_flux) best_flux = flux, best_z = z;
  }
  std::printf("brightest spot at %.2f mm (f = %.1f mm)\n", best_z, kFocal);
  EXPECT_NEAR(best_z / kFocal, 1.0, 0.01) << "brightest at " << best_z << " mm, f = " << kFocal << " mm";
}
