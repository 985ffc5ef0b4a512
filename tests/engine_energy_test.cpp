// SPDX-License-Identifier: LGPL-2.1-or-later
// Energy bookkeeping over random poses (docs/physics.md ch. 5): the summed
// screen flux equals the flux that enters the triangles that reach the
// screen, summed triangle by triangle in double precision on the CPU. The
// sum shares the per-vertex rays (caustic/vertex_rays.hpp) with the
// engine: what it checks is the splat's bookkeeping (every triangle's flux
// spread, none lost or counted twice, folds included), on the GL's shaders
// or the CPU's raster; the rays' physics have their own oracles.
#include "gl_test_support.hpp"

#include "caustic/vertex_rays.hpp"

#include <cstdio>
#include <random>

using namespace caustic;
using namespace caustic::testing;

namespace {

struct Pose {
  Scene scene;
  std::string label;
};

// A random but representable pose: object tilted, light from the flat side
// or the caustic side, directional or point, screen 20-120 mm away.
Pose random_pose(std::mt19937& rng, bool fresnel) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Scene s = straight_down_scene(3.0, 60.0, 10.0, 512);
  s.render.fresnel = fresnel;
  const bool caustic_first = u(rng) < 0.3;
  s.object.rotation_deg = {40 * (u(rng) - 0.5), 40 * (u(rng) - 0.5), 360 * u(rng)};
  if (caustic_first) s.object.rotation_deg.x += 180;  // flat face toward the screen
  s.object.ior = 1.3 + 0.5 * u(rng);
  const double tilt = 0.5 * u(rng), azimuth = 6.283 * u(rng);
  const glm::dvec3 toward_screen(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                                 -std::cos(tilt));
  if (u(rng) < 0.5) {
    s.light.type = LightType::point;
    s.light.point_model = u(rng) < 0.5 ? PointModel::exact : PointModel::approximate;
    s.light.position = -toward_screen * (40.0 + 200.0 * u(rng));
  } else {
    s.light.direction = toward_screen;
  }
  s.screen.center = {0, 0, -(20.0 + 100.0 * u(rng))};
  const std::string label = std::string(s.light.type == LightType::point ? "point" : "directional") +
                            (caustic_first ? ", caustic face first" : ", flat face first");
  return {s, label};
}

}  // namespace

class Energy : public GlTest {
 protected:
  void check_poses(const Mesh& mesh_value, int poses, unsigned seed, bool fresnel) {
    const auto mesh = shared(mesh_value);
    std::mt19937 rng(seed);
    double worst = 0;
    int checked = 0;
    for (int i = 0; i < poses; ++i) {
      Pose pose = random_pose(rng, fresnel);
      FluxSummary expected;
      try {
        check_geometry(pose.scene, *mesh, place_object(pose.scene.object, *mesh));
      } catch (const SceneError&) {
        continue;  // e.g. the point light landed inside the tilted slab
      }
      if (!frame_screen(pose.scene, *mesh, &expected)) continue;
      const HdrImage img = render(pose.scene, mesh);
      ASSERT_TRUE(all_finite(img)) << pose.label;
      ++checked;
      const double measured = total_flux(img, pose.scene.screen);
      const double error = std::abs(measured - expected.flux) / expected.flux;
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-3) << "pose " << i << " (" << pose.label << "): GPU " << measured << ", CPU "
                             << expected.flux << ", " << expected.valid_triangles << " triangles, "
                             << engine_->stats().folded << " folded";
      EXPECT_EQ(engine_->stats().drawn, expected.valid_triangles) << "pose " << i;
    }
    std::printf("worst relative flux error over %d of %d poses: %.2e\n", checked, poses, worst);
    EXPECT_GE(3 * checked, 2 * poses) << "most poses must light the screen";
  }
};

TEST_F(Energy, LensWithoutFresnelKeepsTheEnteringFlux) {
  check_poses(grid_mesh(plano_convex_lens(40.0, 10.0), 96, 96), 30, 1, false);
}

TEST_F(Energy, WavyWindowWithFoldsKeepsTheEnteringFlux) {
  check_poses(grid_mesh(sine_window(0.4, 1.2, 0.3, 0.9, 10.0), 96, 96), 30, 2, false);
}

TEST_F(Energy, FresnelLossesMatchTheCpuModel) {
  check_poses(grid_mesh(sine_window(0.4, 1.2, 0.3, 0.9, 10.0), 64, 64), 20, 3, true);
}
