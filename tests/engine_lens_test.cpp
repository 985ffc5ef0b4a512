// The plano-convex lens against its exact rotationally symmetric ray map
// (docs/physics.md ch. 7), traced here in 2D with scalar trigonometry so the
// oracle shares nothing with the engine.
#include "gl_test_support.hpp"

#include <cmath>
#include <cstdio>

using namespace caustic;
using namespace caustic::testing;

namespace {

constexpr double kRadius = 40.0;  // radius of curvature
constexpr double kIor = 1.5;
constexpr double kFocal = kRadius / (kIor - 1.0);

// Screen radius of the ray that enters the flat face at radius r (parallel
// light along -z, flat face up, apex at z = 0), screen at z = -distance.
double ray_map(double r, double distance) {
  const double root = std::sqrt(kRadius * kRadius - r * r);
  const double surface_z = kRadius - root;
  // Outward normal (r, -root) / R; inside, the ray travels along -z.
  const double sin_i = r / kRadius;                 // angle between ray and normal
  const double sin_t = kIor * sin_i;                // leaving glass
  const double deviation = std::asin(sin_t) - std::asin(sin_i);  // toward the axis
  return r - (surface_z + distance) * std::tan(deviation);
}

// Radius where the ray map folds over (d rs / d r = 0): the focus ring.
// Before it the map increases; after it, decreases. r_max if it never folds.
double fold_radius(double distance, double r_max) {
  const double h = 1e-6;
  auto slope = [&](double r) { return (ray_map(r + h, distance) - ray_map(r - h, distance)) / (2 * h); };
  if (slope(r_max) > 0) return r_max;
  double lo = 0.0, hi = r_max;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slope(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The preimage radius of screen radius rs on the monotone branch [a, b]
// (increasing or decreasing), or a negative value when rs is not reached.
double preimage(double rs, double distance, double a, double b) {
  const double fa = ray_map(a, distance), fb = ray_map(b, distance);
  if ((rs - fa) * (rs - fb) > 0) return -1;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (a + b);
    ((ray_map(mid, distance) - rs) * (fa - rs) > 0 ? a : b) = mid;
  }
  return 0.5 * (a + b);
}

}  // namespace

class PlanoConvexLens : public GlTest {};

TEST_F(PlanoConvexLens, ProfileMatchesTheExactRayMapBeforeFocus) {
  // E(rs) = sum over branches of r / (rs |d rs / d r|), over the preimages r
  // that lie inside the square aperture. Pixels within a few pixels of a
  // caustic (the focus ring, where d rs / d r = 0) or of the image of the
  // aperture's edge are left out: there a pixel's average and the value at
  // its centre legitimately differ.
  const double half = 10.0, corner = half * std::sqrt(2.0);
  const auto lens = shared(grid_mesh(plano_convex_lens(kRadius, half), 256, 256));
  for (const double z : {20.0, 40.0, 60.0}) {
    const double r_fold = fold_radius(z, corner);
    const double rs_max = ray_map(r_fold, z);
    Scene s = straight_down_scene(4.0, z, 2.0 * rs_max + 1.0, 384);
    const HdrImage img = render(s, lens);
    ASSERT_TRUE(all_finite(img));
    const double pixel = s.screen.width / img.width;
    double diff = 0, sum = 0;
    int used = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const glm::dvec2 p = pixel_centre(s.screen, img.width, img.height, x, y);
        const double rs = glm::length(p);
        if (rs < 2 * pixel || rs > rs_max - 4 * pixel) continue;  // axis; focus ring
        const glm::dvec2 dir = p / rs;
        const double r_edge = half / std::max(std::abs(dir.x), std::abs(dir.y));  // aperture edge
        double e = 0;
        bool near_edge = false;
        for (const auto& [a, b] : {std::pair{0.0, r_fold}, std::pair{r_fold, corner}}) {
          const double r = preimage(rs, z, a, b);
          if (r < 0 || r > r_edge) continue;
          const double h = 1e-6;
          const double slope = (ray_map(r + h, z) - ray_map(r - h, z)) / (2 * h);
          if (std::abs(ray_map(r_edge, z) - rs) < 4 * pixel) near_edge = true;
          e += r / (rs * std::abs(slope));
        }
        if (near_edge || std::abs(ray_map(std::min(r_edge, r_fold), z) - rs) < 4 * pixel) continue;
        diff += std::abs(img.at(x, y) - e);
        sum += e;
        ++used;
      }
    std::printf("z = %.0f mm: relative L1 %.4f over %d pixels\n", z, diff / sum, used);
    EXPECT_GT(used, 10000) << "z = " << z;
    EXPECT_LT(diff / sum, 0.03) << "relative L1 at z = " << z;
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
