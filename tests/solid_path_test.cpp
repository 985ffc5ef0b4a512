// SPDX-License-Identifier: LGPL-2.1-or-later
// The multipass tracer's ray through a solid, against closed-form optics:
// a biconvex lens traced sphere by sphere in the test itself, the thick-lens
// (lensmaker's) focal length, Fresnel's series inside a plate, Snell's
// invariance through stacked plates, and a ray that can never leave.
#include "caustic/light_grid.hpp"
#include "caustic/optics.hpp"
#include "caustic/solid_path.hpp"
#include "caustic/surfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace caustic;

namespace {

constexpr double kR = 50, kD = 4, kHalf = 5, kN = 1.5;

// The biconvex lens of these tests: both radii kR, kD thick on the axis.
const Mesh& lens() {
  static const Mesh mesh = biconvex_lens(kR, kR, kD, kHalf, 257);
  return mesh;
}

// Snell's law as the conservation of the ray's component along the surface:
// it scales by eta = n_from / n_to, the normal component makes up a unit
// vector. Written here rather than taken from optics::refract, the code
// under test. `n` is the unit normal, either side.
glm::dvec3 snell(const glm::dvec3& d, glm::dvec3 n, double eta) {
  if (glm::dot(n, d) > 0) n = -n;
  const glm::dvec3 along = eta * (d - glm::dot(d, n) * n);
  return along - std::sqrt(1 - glm::dot(along, along)) * n;
}

// Closed form: where a ray straight down at (x, y) crosses the plane z = z_screen
// after refracting at the upper sphere (centre (0, 0, d/2 - R)) and the lower
// one (centre (0, 0, -d/2 + R)).
glm::dvec2 exact_landing(double x, double y, double z_screen) {
  using optics::Vec3;
  const Vec3 c1(0, 0, kD / 2 - kR), c2(0, 0, -kD / 2 + kR);
  Vec3 o(x, y, 10), d(0, 0, -1);
  auto sphere = [](const Vec3& o, const Vec3& d, const Vec3& c, double r, bool far) {
    const double b = glm::dot(o - c, d), k = glm::dot(o - c, o - c) - r * r;
    const double root = std::sqrt(b * b - k);
    return o + (far ? -b + root : -b - root) * d;
  };
  const Vec3 p1 = sphere(o, d, c1, kR, false);  // entering the upper cap from above
  d = snell(d, glm::normalize(p1 - c1), 1 / kN);
  const Vec3 p2 = sphere(p1, d, c2, kR, true);  // the lower cap: leaving its sphere from inside
  d = snell(d, glm::normalize(p2 - c2), kN);
  const Vec3 hit = p2 + ((z_screen - p2.z) / d.z) * d;
  return {hit.x, hit.y};
}

}  // namespace

TEST(SolidPath, ABiconvexLensMatchesItsTwoSpheresRayByRay) {
  const Solid solid(lens(), Placement{});
  for (const double r : {0.3, 1.0, 2.5, 4.0, 4.9}) {
    const glm::dvec2 at(r * 0.6, r * 0.8);
    const SolidPath path = follow_solid(solid, {at.x, at.y, 10}, {0, 0, -1}, kN, false, FresnelSplit::weight);
    ASSERT_TRUE(path.valid) << r;
    EXPECT_EQ(path.events, 2);
    const glm::dvec2 got(path.origin + ((-60 - path.origin.z) / path.dir.z) * path.dir);
    const glm::dvec2 want = exact_landing(at.x, at.y, -60);
    // The faces are triangles 10/256 mm across, their vertices on the
    // spheres with exact normals: measured within 1.3e-6 mm, the float
    // positions' rounding; a chord's sag between vertices would be 4e-6.
    EXPECT_NEAR(got.x, want.x, 2e-5) << r;
    EXPECT_NEAR(got.y, want.y, 2e-5) << r;
  }
}

TEST(SolidPath, ParaxialRaysCrossTheAxisAtTheLensmakersBackFocalLength) {
  // Thick lens: 1/f = (n-1)(1/R1 + 1/R2 - (n-1)d/(n R1 R2)); BFL = f (1 - (n-1)d/(n R1)).
  const double f = 1 / ((kN - 1) * (2 / kR - (kN - 1) * kD / (kN * kR * kR)));
  const double bfl = f * (1 - (kN - 1) * kD / (kN * kR));
  const Solid solid(lens(), Placement{});
  const SolidPath path = follow_solid(solid, {0, 0.2, 10}, {0, 0, -1}, kN, false, FresnelSplit::weight);
  ASSERT_TRUE(path.valid);
  const double z = path.origin.z - path.origin.y / path.dir.y * path.dir.z;
  // Measured 1.2e-3 mm short of paraxial, the spherical aberration of a ray
  // 0.2 mm off the axis; a 0.1% error in the index moves it by 0.1 mm.
  EXPECT_NEAR(z, -kD / 2 - bfl, 5e-3) << "f " << f << " bfl " << bfl;
}

TEST(SolidPath, APlateTransmitsTheFresnelProductAndSamplingAddsTheInternalEchoes) {
  const HeightField top{[](double, double) { return 1.0; }, [](double, double) { return glm::dvec2(0.0); }, 5, 5};
  const Mesh plate = closed_body(top, flat_face(5), 9);
  const Solid solid(plate, Placement{});
  const double r = std::pow((kN - 1) / (kN + 1), 2);
  const SolidPath weighted = follow_solid(solid, {0.3, 0.1, 5}, {0, 0, -1}, kN, true, FresnelSplit::weight);
  ASSERT_TRUE(weighted.valid);
  EXPECT_NEAR(weighted.transmittance, (1 - r) * (1 - r), 1e-12);
  // Sampling follows the reflections too: down through the plate with
  // probability T^2 (1 + R^2 + R^4 + ...) = (1 - R) / (1 + R).
  std::mt19937_64 rng(7);
  const int photons = 40000;
  int down = 0;
  for (int i = 0; i < photons; ++i) {
    const SolidPath p = follow_solid(solid, {0.3, 0.1, 5}, {0, 0, -1}, kN, true, FresnelSplit::sample, &rng);
    if (p.valid && p.dir.z < 0) ++down;
  }
  const double expected = (1 - r) / (1 + r), sigma = std::sqrt(expected * (1 - expected) / photons);
  EXPECT_NEAR(static_cast<double>(down) / photons, expected, 4 * sigma);
}

TEST(SolidPath, StackedPlatesLeaveATiltedRayParallelToItself) {
  // Two plates in one mesh with air between: four interfaces, and Snell's
  // invariant n sin(theta) brings the ray out as it came in.
  const HeightField t1{[](double, double) { return 3.0; }, [](double, double) { return glm::dvec2(0.0); }, 5, 5};
  const HeightField b1{[](double, double) { return 2.0; }, [](double, double) { return glm::dvec2(0.0); }, 5, 5};
  const HeightField t2{[](double, double) { return 1.0; }, [](double, double) { return glm::dvec2(0.0); }, 5, 5};
  Mesh stack = closed_body(t1, b1, 5);
  const Mesh lower = closed_body(t2, flat_face(5), 5);
  const auto base = static_cast<unsigned>(stack.positions.size());
  stack.positions.insert(stack.positions.end(), lower.positions.begin(), lower.positions.end());
  stack.normals.insert(stack.normals.end(), lower.normals.begin(), lower.normals.end());
  for (const auto& t : lower.triangles) stack.triangles.push_back(t + glm::uvec3(base));
  EXPECT_NO_THROW(check_closed(stack));
  const Solid solid(stack, Placement{});
  const glm::dvec3 in = glm::normalize(glm::dvec3(0.3, 0.1, -1));
  const SolidPath path = follow_solid(solid, {-0.5, 0, 5}, in, kN, false, FresnelSplit::weight);
  ASSERT_TRUE(path.valid);
  EXPECT_EQ(path.events, 4);
  EXPECT_NEAR(glm::length(path.dir - in), 0, 1e-9);
}

TEST(SolidPath, ARayTrappedByTotalInternalReflectionStops) {
  // n = 10: every face reflects a ray this oblique, for ever; the tracer gives up.
  const HeightField top{[](double, double) { return 2.0; }, [](double, double) { return glm::dvec2(0.0); }, 1, 1};
  const Mesh box = closed_body(top, flat_face(1), 3);
  const Solid solid(box, Placement{});
  const SolidPath path =
      follow_solid(solid, {0.1, -0.2, 1}, glm::normalize(glm::dvec3(0.5, 0.6, 0.62)), 10.0, true, FresnelSplit::weight);
  EXPECT_FALSE(path.valid);
  EXPECT_GT(path.events, kMaxSolidEvents);
}

TEST(SolidPath, ClosedBodiesPassAndOpenOrInvertedOnesAreRefused) {
  EXPECT_NO_THROW(check_closed(lens()));
  Mesh open = lens();
  open.triangles.pop_back();
  try {
    check_closed(open);
    FAIL() << "an open mesh passed";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "mesh");
    EXPECT_NE(std::string(e.what()).find("3 edges"), std::string::npos) << e.what();
  }
  Mesh inverted = lens();
  for (auto& t : inverted.triangles) std::swap(t.y, t.z);
  EXPECT_THROW(check_closed(inverted), SceneError);
}

TEST(LightGrid, RaysBesideTheSolidCarryNothingAndPartedTrianglesBecomeSampledPoints) {
  Scene scene;
  scene.object.shape = Shape::solid;
  scene.screen.center = {0, 0, -30};
  scene.render.fresnel = false;
  const Solid solid(lens(), Placement{});
  const LandedGrid grid = trace_light_grid(scene, solid, kN, 64, 2);
  EXPECT_GT(grid.split, 0u);  // the rim
  std::size_t points = 0;
  for (const auto& t : grid.triangles) {
    const auto& a = grid.vertices[t.x];
    EXPECT_EQ(a.valid, 1.0f);
    if (a.share < 1) {
      ++points;
      EXPECT_EQ(a.screen, grid.vertices[t.y].screen);
      EXPECT_EQ(a.screen, grid.vertices[t.z].screen);
    }
  }
  EXPECT_GT(points, grid.split);  // up to 16 a parted triangle
  EXPECT_LE(points, 16 * grid.split);
  EXPECT_EQ(grid.rays, 64u * 64u + 16 * grid.split);
}
