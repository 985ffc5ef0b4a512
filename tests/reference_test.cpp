// SPDX-License-Identifier: LGPL-2.1-or-later
// The reference photon tracer against the analytic oracles, before it is
// trusted to judge the engine.
#include "caustic/image_compare.hpp"
#include "caustic/optics.hpp"
#include "caustic/reference.hpp"
#include "caustic/resample.hpp"
#include "caustic/surfaces.hpp"
#include "lens_oracle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

using namespace caustic;

namespace {

Scene straight_down(double flat_offset, double distance, double screen_size, int pixels, bool fresnel) {
  Scene s;
  s.mesh = "generated";
  s.object.flat_face_offset = flat_offset;
  s.screen.center = {0, 0, -distance};
  s.screen.width = s.screen.height = screen_size;
  s.render.width = s.render.height = pixels;
  s.render.fresnel = fresnel;
  return s;
}

ReferenceOptions photons(std::uint64_t n, int threads = 0) {
  ReferenceOptions o;
  o.photons = n;
  o.threads = threads;
  return o;
}

}  // namespace

TEST(Reference, FlatSlabIsUniformTinTout) {
  const Mesh slab = grid_mesh(flat_face(10.0), 16, 16);
  // 0.4 mm pixels: the slab's edges fall on pixel boundaries.
  const ReferenceResult r = trace_reference(straight_down(3.0, 50.0, 25.6, 64, true), slab, photons(4'000'000));
  const double expected = 0.96 * 0.96;
  double worst = 0, mean = 0;
  for (int y = 8; y < 56; ++y)
    for (int x = 8; x < 56; ++x) {
      worst = std::max(worst, std::abs(r.image.at(x, y) - expected) / expected);
      mean += r.image.at(x, y) / (48.0 * 48.0);
    }
  EXPECT_NEAR(mean, expected, 0.003 * expected);
  // Strata do not line up with pixels: a pixel holds 39 or 40 columns of
  // them, so single pixels scatter by up to ~2.5% around the mean.
  EXPECT_LT(worst, 0.04);
  // The shadow's edges lie on pixel boundaries (x, y = ±10 mm at pixels 7
  // and 57): every photon binned where it landed lights pixels 7 to 56, the
  // edge ones as fully as the rest, and next to nothing beside them (a
  // photon that grazes the mesh's float edge is 6e-4 of a pixel's light).
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool lit = x >= 7 && x <= 56 && y >= 7 && y <= 56;
      EXPECT_NEAR(r.image.at(x, y), lit ? expected : 0.0, (lit ? 0.04 : 0.01) * expected) << x << "," << y;
    }
  std::printf("slab: %llu photons in %.2f s (%.1f M photons/s)\n", static_cast<unsigned long long>(r.photons),
              r.seconds, r.photons / r.seconds / 1e6);
}

TEST(Reference, PlanoConvexLensMatchesTheExactRayMap) {
  const double half = 10.0;
  const Mesh lens = grid_mesh(plano_convex_lens(oracle::kRadius, half), 128, 128);
  for (const double z : {20.0, 60.0}) {
    const Scene s = straight_down(4.0, z, oracle::lens_screen_size(z, half), 96, false);
    const ReferenceResult r = trace_reference(s, lens, photons(4'000'000));
    const auto [l1, used] = oracle::compare_with_ray_map(r.image, s.screen.width, z, half);
    std::printf("lens at %.0f mm: relative L1 %.4f over %d pixels, %.1f M photons/s\n", z, l1, used,
                r.photons / r.seconds / 1e6);
    EXPECT_GT(used, 3000);
    EXPECT_LT(l1, 0.03) << "z = " << z;
  }
}

namespace {
// A point light over an index-1 window (glass that bends nothing), 32²
// pixels of a 40 mm screen: light whose landing is known in closed form.
Scene point_light_over_air() {
  Scene s = straight_down(2.0, 40.0, 40.0, 32, false);
  s.object.ior = 1.0;
  s.light.type = LightType::point;
  s.light.position = {0.3, -0.2, 30};
  return s;
}
}  // namespace

TEST(Reference, ErrorFallsAsOneOverSqrtPhotons) {
  // Flux through a point light's index-1 window: E / E0 = r_ref^2 cos / r^2,
  // known exactly, so the Monte Carlo error itself can be measured.
  const Scene s = point_light_over_air();
  const Mesh window = grid_mesh(flat_face(25.0), 8, 8);
  auto error = [&](std::uint64_t n) {
    const ReferenceResult r = trace_reference(s, window, photons(n));
    double diff = 0, sum = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const double px = (x + 0.5) * 40.0 / 32 - 20, py = 20 - (y + 0.5) * 40.0 / 32;
        const glm::dvec3 to(px - 0.3, py + 0.2, -70.0);
        const double r2 = glm::dot(to, to);
        const double exact = glm::dot(s.light.position - glm::dvec3(0, 0, 0), s.light.position) * (70.0 / std::sqrt(r2)) / r2;
        diff += std::abs(r.image.at(x, y) - exact);
        sum += exact;
      }
    return diff / sum;
  };
  const double coarse = error(10'000), fine = error(640'000);  // 64x the photons
  std::printf("relative L1: %.4f at 1e4 photons, %.4f at 6.4e5 photons (ratio %.1f)\n", coarse, fine, coarse / fine);
  // Unbiased, the error falls at least as 1 / sqrt(N) (8x for 64x the
  // photons; stratified, faster): 6x leaves room for the noise in the
  // coarse figure, and a bias of a few percent would hold `fine` above it.
  EXPECT_LT(fine, coarse / 6);
  EXPECT_LT(fine, 0.05);
}

TEST(Reference, APointLightsFluxIsTheSolidAngleOfTheScreen) {
  // Index-1 glass wider than the cone from the light to the screen: every
  // photon towards the screen lands on it, so the landed flux (E0 units
  // times mm²) is r_ref² times the solid angle of the screen's rectangle
  // seen from the light, in closed form: the sum over its corners of
  // ±atan(x y / (d √(x² + y² + d²))). Summed over the image, the photons'
  // noise averages out, and a bias of a percent shows.
  const Scene s = point_light_over_air();
  const Mesh window = grid_mesh(flat_face(25.0), 8, 8);
  const ReferenceResult r = trace_reference(s, window, photons(640'000));
  const double pixel = (40.0 / 32) * (40.0 / 32);
  double landed = 0;
  for (float e : r.image.pixels) landed += e * pixel;
  const double d = 70.0, x[2] = {-20 - 0.3, 20 - 0.3}, y[2] = {-20 + 0.2, 20 + 0.2};
  double omega = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      omega += (i == j ? 1 : -1) * std::atan(x[i] * y[j] / (d * std::sqrt(x[i] * x[i] + y[j] * y[j] + d * d)));
  const double r_ref2 = glm::dot(s.light.position, s.light.position);  // to the object's centre, the origin
  std::printf("point light: landed %.6f of r_ref^2 times the screen's solid angle\n", landed / (r_ref2 * omega));
  EXPECT_NEAR(landed / (r_ref2 * omega), 1.0, 2e-3);
}

TEST(Reference, DeterministicForASeedWhateverTheThreads) {
  const Mesh lens = grid_mesh(plano_convex_lens(40.0, 10.0), 32, 32);
  const Scene s = straight_down(4.0, 30.0, 20.0, 32, true);
  const ReferenceResult one = trace_reference(s, lens, photons(40'000, 1));
  const ReferenceResult two = trace_reference(s, lens, photons(40'000, 2));
  EXPECT_EQ(one.image.pixels, two.image.pixels);
  ReferenceOptions other = photons(40'000, 2);
  other.seed = 2;
  EXPECT_NE(trace_reference(s, lens, other).image.pixels, one.image.pixels);
}

TEST(Reference, RejectsWhatTheSceneCannotRepresent) {
  const Mesh lens = grid_mesh(plano_convex_lens(40.0, 10.0), 16, 16);
  Scene s = straight_down(4.0, 30.0, 20.0, 32, true);
  s.screen.center = {0, 0, 1};
  EXPECT_THROW(trace_reference(s, lens, photons(100)), SceneError);
  s = straight_down(4.0, 30.0, 20.0, 32, true);
  s.object.ior = std::nan("");
  EXPECT_THROW(trace_reference(s, lens, photons(100)), SceneError);
}

TEST(Resample, LensAtAnotherResolutionIsTheSameSurface) {
  const auto surface = plano_convex_lens(oracle::kRadius, 10.0);
  const Mesh fine = grid_mesh(surface, 96, 96);
  const Mesh coarse = resample_face(fine, {0, 0, 1}, 33);
  EXPECT_EQ(coarse.positions.size(), 33u * 33u);
  EXPECT_EQ(coarse.triangles.size(), 2u * 32u * 32u);
  double worst_height = 0, worst_normal = 0;
  for (std::size_t i = 0; i < coarse.positions.size(); ++i) {
    const glm::dvec3 p = coarse.positions[i];
    worst_height = std::max(worst_height, std::abs(p.z - surface.height(p.x, p.y)));
    const glm::dvec2 g = surface.gradient(p.x, p.y);
    const glm::dvec3 exact = glm::normalize(glm::dvec3(g.x, g.y, -1.0));
    worst_normal = std::max(worst_normal, glm::length(glm::dvec3(coarse.normals[i]) - exact));
  }
  // Chord error of the 96^2 source (flat triangles on a sphere) and its
  // linearly interpolated normals bound what resampling can reproduce.
  EXPECT_LT(worst_height, 2e-3);
  EXPECT_LT(worst_normal, 2e-3);
  EXPECT_THROW(resample_face(fine, {0, 0, 1}, 1), std::invalid_argument);
}

TEST(Resample, KeepsTheTintInterpolatedWhereEachVertexLands) {
  // A linear colour ramp is reproduced exactly by linear interpolation.
  Mesh fine = grid_mesh(plano_convex_lens(oracle::kRadius, 10.0), 24, 24);
  auto ramp = [](const glm::dvec3& p) { return glm::dvec3(0.5 + p.x / 25, 0.5 - p.y / 25, 0.25); };
  for (const auto& p : fine.positions) fine.colours.emplace_back(ramp(p));
  const Mesh coarse = resample_face(fine, {0, 0, 1}, 9);
  ASSERT_EQ(coarse.colours.size(), coarse.positions.size());
  for (std::size_t i = 0; i < coarse.positions.size(); ++i)
    EXPECT_NEAR(glm::length(glm::dvec3(coarse.colours[i]) - ramp(coarse.positions[i])), 0.0, 1e-4) << i;
  EXPECT_NO_THROW(validate_mesh(coarse));
  EXPECT_FALSE(tinted(resample_face(grid_mesh(plano_convex_lens(oracle::kRadius, 10.0), 24, 24), {0, 0, 1}, 9)));
}

// The measures docs/accuracy.md quotes, against figures worked by hand:
// box filter means, relative L1 and RMSE of a known difference, and SSIM in
// its closed forms (constant windows: (2ab + C1) / (a² + b² + C1); a pattern
// of deviation s against its flat mean: C2 / (s² + C2)).
TEST(ImageCompare, BoxFilterAndErrorsAreTheirDefinitions) {
  HdrImage ramp{4, 2, {0, 1, 2, 3, 4, 5, 6, 7}};
  const HdrImage half = box_down(ramp, 2);
  ASSERT_EQ(half.width, 2);
  ASSERT_EQ(half.height, 1);
  EXPECT_FLOAT_EQ(half.pixels[0], 2.5f);
  EXPECT_FLOAT_EQ(half.pixels[1], 4.5f);
  EXPECT_THROW(box_down(ramp, 3), std::invalid_argument);
  EXPECT_THROW(box_down(ramp, 0), std::invalid_argument);

  // 64 pixels of 2: four 1 too bright, four 0.5 too dark.
  HdrImage reference{8, 8, std::vector<float>(64, 2.0f)}, image = reference;
  for (int k = 0; k < 4; ++k) image.pixels[k] += 1.0f, image.pixels[60 + k] -= 0.5f;
  const ImageError e = compare(image, reference);
  EXPECT_NEAR(e.relative_l1, 6.0 / 128.0, 1e-12);
  EXPECT_NEAR(e.relative_rmse, std::sqrt(5.0 / 64.0) / 2.0, 1e-12);
  EXPECT_NEAR(compare(reference, reference).ssim, 1.0, 1e-12);
  EXPECT_THROW(compare(image, HdrImage{8, 7, std::vector<float>(56, 1.0f)}), std::invalid_argument);
  EXPECT_THROW(compare(image, HdrImage{8, 8, std::vector<float>(64, 0.0f)}), std::invalid_argument);
}

TEST(ImageCompare, SsimHasItsClosedForms) {
  const double exposure = 1.0, gamma = 2.2, c1 = 1e-4, c2 = 9e-4;
  const auto shown = [&](double e) { return std::pow(1 - std::exp(-exposure * e), 1 / gamma); };
  const auto irradiance = [&](double t) { return -std::log(1 - std::pow(t, gamma)) / exposure; };
  const HdrImage one{16, 16, std::vector<float>(256, 1.0f)}, two{16, 16, std::vector<float>(256, 2.0f)};
  const double a = shown(1.0), b = shown(2.0);
  EXPECT_NEAR(tonemapped_ssim(one, two, exposure, gamma), (2 * a * b + c1) / (a * a + b * b + c1), 1e-9);
  // A checkerboard showing m ± s: every 8 x 8 window holds 32 of each.
  const double m = 0.5, dev = 0.1;
  HdrImage board{16, 16, std::vector<float>(256)}, flat{16, 16, std::vector<float>(256, static_cast<float>(irradiance(m)))};
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      board.pixels[static_cast<std::size_t>(y) * 16 + x] = static_cast<float>(irradiance((x + y) % 2 ? m + dev : m - dev));
  EXPECT_NEAR(tonemapped_ssim(board, flat, exposure, gamma), c2 / (dev * dev + c2), 1e-5);
  // Against itself, and against the same board at half the contrast:
  // (2 k s² + C2) / ((1 + k²) s² + C2) with k = 1/2.
  EXPECT_NEAR(tonemapped_ssim(board, board, exposure, gamma), 1.0, 1e-12);
  HdrImage softer = board;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      softer.pixels[static_cast<std::size_t>(y) * 16 + x] =
          static_cast<float>(irradiance((x + y) % 2 ? m + dev / 2 : m - dev / 2));
  EXPECT_NEAR(tonemapped_ssim(board, softer, exposure, gamma), (dev * dev + c2) / (1.25 * dev * dev + c2), 1e-5);
  EXPECT_THROW(tonemapped_ssim(HdrImage{4, 4, std::vector<float>(16, 1.0f)}, HdrImage{4, 4, std::vector<float>(16, 1.0f)},
                               exposure, gamma),
               std::invalid_argument);
}
