// SPDX-License-Identifier: LGPL-2.1-or-later
// The multipass method on the GPU splat: a biconvex lens (object.shape
// "solid") conserves the flux it lets in, focuses at the thick lens's back
// focal length, and loses what Fresnel says it loses.
#include "gl_test_support.hpp"

#include "caustic/optics.hpp"

#include <cstdio>
#include <utility>
#include <vector>

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

// The oracle: the lens as the two spheres its mesh samples, traced exactly
// (vector Snell's law at each) for a square grid of rays straight down
// over its aperture; shares no code with the engine or its tracer.
class SphericalLens {
 public:
  static SphericalLens traced(double r, double thickness, double half, double n, int rays) {
    SphericalLens lens;
    const glm::dvec3 upper(0, 0, thickness / 2 - r), lower(0, 0, -thickness / 2 + r), down(0, 0, -1);
    for (int i = 0; i < rays; ++i)
      for (int j = 0; j < rays; ++j) {
        const double x = ((i + 0.5) / rays * 2 - 1) * half, y = ((j + 0.5) / rays * 2 - 1) * half;
        const glm::dvec3 in(x, y, upper.z + std::sqrt(r * r - x * x - y * y));
        const glm::dvec3 d = snell(down, (in - upper) / r, 1 / n);
        // Out through the lower sphere, the far side of it from `in`.
        const glm::dvec3 o = in - lower;
        const double b = glm::dot(o, d), t = -b + std::sqrt(b * b - glm::dot(o, o) + r * r);
        const glm::dvec3 out = in + t * d;
        lens.rays_.push_back({out, snell(d, (lower - out) / r, n)});
      }
    return lens;
  }

  // Share of the rays within `radius` of the axis at height z.
  double encircled(double z, double radius) const {
    std::size_t inside = 0;
    for (const auto& [p, d] : rays_) {
      const glm::dvec3 at = p + (z - p.z) / d.z * d;
      if (at.x * at.x + at.y * at.y < radius * radius) ++inside;
    }
    return static_cast<double>(inside) / static_cast<double>(rays_.size());
  }

 private:
  // Unit `d` refracted at a surface whose unit normal `m` faces against it, eta = n1 / n2.
  static glm::dvec3 snell(glm::dvec3 d, glm::dvec3 m, double eta) {
    const double c = -glm::dot(d, m);
    return eta * d + (eta * c - std::sqrt(1 - eta * eta * (1 - c * c))) * m;
  }
  std::vector<std::pair<glm::dvec3, glm::dvec3>> rays_;
};

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
  const auto oracle = SphericalLens::traced(kR, kD, kHalf, kN, 200);
  // Spherical aberration of this 10 mm aperture moves the tightest spot
  // ahead of the paraxial focus, here by 0.5-1 mm; the scan steps 0.25 mm.
  // The circle (30 um) is smaller than every spot in the scan, so the
  // largest share is unique: a wider one holds all the light at several
  // depths and the tie is decided by rounding.
  double best = 0, best_z = 0, expected = 0, expected_z = 0;
  for (double z = focus - 1.5; z <= focus + 1.5; z += 0.25) {
    const Scene s = lens_scene(z, 2, 256);
    const double share = encircled(render(s, lens()), s.screen, 0.03), traced = oracle.encircled(z, 0.03);
    std::printf("z %.3f: %.4f of the light within 30 um (traced through the spheres: %.4f)\n", z, share, traced);
    if (share > best) best = share, best_z = z;
    if (traced > expected) expected = traced, expected_z = z;
  }
  // The paraxial (lensmaker's) focus bounds it on one side, and the spheres
  // traced exactly put it in one step of the scan: a thin lens's focus, or
  // the paraxial one, lies at least two steps away.
  EXPECT_GT(best_z, focus) << "paraxial focus " << focus;
  EXPECT_NEAR(best_z, expected_z, 0.125) << "paraxial focus " << focus;
  EXPECT_NEAR(best, expected, 0.15);
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
