// SPDX-License-Identifier: LGPL-2.1-or-later
// The multipass method on the GPU splat: a biconvex lens (object.shape
// "solid") conserves the flux it lets in, focuses at the thick lens's back
// focal length, and loses what Fresnel says it loses.
#include "gl_test_support.hpp"

#include "caustic/optics.hpp"

using namespace caustic;
using namespace caustic::testing;

namespace {

constexpr double kR = 50, kD = 4, kHalf = 5, kN = 1.5;

std::shared_ptr<const Mesh> lens() {
  static const auto mesh = shared(biconvex_lens(kR, kR, kD, kHalf, 129));
  return mesh;
}

// Light straight down on the lens, a screen at height z below it.
Scene lens_scene(double z, double size, int pixels) {
  Scene s = straight_down_scene(0, -z, size, pixels);
  s.object.flat_face_offset.reset();
  s.object.shape = Shape::solid;
  s.object.ior = kN;
  s.render.light_grid = 256;
  return s;
}

// Share of the flux within `radius` of the screen's centre.
double encircled(const HdrImage& img, const ScreenParams& screen, double radius) {
  double inside = 0, all = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double v = img.pixels[static_cast<std::size_t>(y) * img.width + x];
      all += v;
      if (glm::length(pixel_centre(screen, img.width, img.height, x, y)) < radius) inside += v;
    }
  return inside / all;
}

}  // namespace

class EngineSolid : public GlTest {};

TEST_F(EngineSolid, ALensWithoutFresnelDeliversAllTheLightThatFallsOnIt) {
  const Scene s = lens_scene(-20, 14, 512);
  const HdrImage img = render(s, lens());
  ASSERT_TRUE(all_finite(img));
  // Every ray into the 10 x 10 mm aperture leaves through the lower face.
  const double flux = total_flux(img, s.screen);
  // The rim's parted strip, sampled finer, leaves under 1e-4 on this grid.
  EXPECT_NEAR(flux / (4 * kHalf * kHalf), 1.0, 1e-3) << flux;
  EXPECT_GT(engine_->stats().split, 0u);  // the rim's triangles went as points
}

TEST_F(EngineSolid, FresnelTakesTwoSurfacesWorthOfReflection) {
  Scene s = lens_scene(-20, 14, 256);
  const double off = total_flux(render(s, lens()), s.screen);
  s.render.fresnel = true;
  const double on = total_flux(render(s, lens()), s.screen);
  // Near normal incidence each face passes 1 - R; the faces tilt by at most
  // 8 degrees here, which changes T by under 1e-3.
  const double r = std::pow((kN - 1) / (kN + 1), 2);
  EXPECT_NEAR(on / off, (1 - r) * (1 - r), 2e-3);
}

TEST_F(EngineSolid, TheSpotIsTightestAtTheBackFocalLength) {
  const double f = 1 / ((kN - 1) * (2 / kR - (kN - 1) * kD / (kN * kR * kR)));
  const double focus = -kD / 2 - f * (1 - (kN - 1) * kD / (kN * kR));
  double best = 0, best_z = 0;
  // Spherical aberration of this 10 mm aperture moves the tightest spot
  // ahead of the paraxial focus, here by 0.5-1 mm; the scan steps 0.25 mm.
  // The circle (30 um) is smaller than every spot in the scan, so the
  // largest share is unique: a wider one holds all the light at several
  // depths and the tie is decided by rounding.
  for (double z = focus - 1.5; z <= focus + 1.5; z += 0.25) {
    const Scene s = lens_scene(z, 2, 256);
    const double share = encircled(render(s, lens()), s.screen, 0.03);
    if (share > best) best = share, best_z = z;
  }
  EXPECT_NEAR(best_z, focus, 1.0) << "paraxial focus " << focus;
  EXPECT_GT(best, 0.5);
}

TEST_F(EngineSolid, InGlassItsColoursAddUpToTheGreyFrame) {
  // Dispersion spreads the focus by wavelength (chromatic aberration), but
  // every wavelength's light arrives: the luminance carries the grey flux.
  Scene s = lens_scene(-20, 14, 256);
  const double grey = total_flux(render(s, lens()), s.screen);
  s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
  s.object.ior = s.object.glass->index(optics::kLineD);
  s.render.wavelengths = 8;
  const HdrImage colour = render(s, lens());
  EXPECT_TRUE(engine_->stats().colour);
  EXPECT_EQ(engine_->stats().wavelengths, 8);
  EXPECT_NEAR(total_flux(colour, s.screen) / grey, 1.0, 2e-3);
}

TEST_F(EngineSolid, APreviewThinsTheLightGridAndKeepsTheFlux) {
  const Scene s = lens_scene(-20, 14, 256);
  const double full = total_flux(render(s, lens()), s.screen);
  engine_->set_preview_divisor(4);  // a 64^2 grid on a 64^2 picture
  const HdrImage preview = render(s, lens());
  EXPECT_EQ(preview.width, 64);
  // 64^2 rays over the lens: its rim strip, sampled 16 times finer, still
  // errs by ~0.4% (the full grid's 7e-5 grows as the spacing squared and more).
  EXPECT_NEAR(total_flux(preview, s.screen) / full, 1.0, 1e-2);
}

TEST_F(EngineSolid, AnOpenMeshIsRefusedAndTheLastSceneStays) {
  const Scene s = lens_scene(-20, 14, 64);
  render(s, lens());
  Mesh open = *lens();
  open.triangles.pop_back();
  EXPECT_THROW(engine_->set_scene(s, shared(std::move(open))), SceneError);
  EXPECT_FALSE(engine_->dirty());  // nothing changed
}
