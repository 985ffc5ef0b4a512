// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic pass's two paths draw the same picture: the GL's vertex,
// geometry and fragment stages (caustic.vert, caustic.geom, caustic.frag)
// and their CPU twin (src/engine/cpu_setup.hpp, coverage.hpp) with the GL
// adding its image. Each scene below takes a different branch of the setup;
// the two pictures and triangle counts must agree to float precision.
#include "gl_test_support.hpp"

#include "caustic/water_mesh.hpp"

#include <cmath>
#include <map>
#include <utility>

using namespace caustic;
using namespace caustic::testing;

namespace {

std::shared_ptr<const Mesh> lens_mesh() {
  static const auto mesh = shared(grid_mesh(plano_convex_lens(40.0, 10.0), 65, 65));
  return mesh;
}

// The plano-convex lens seen on a 30 mm screen `distance` below, Fresnel on:
// near its focus (60 mm) the sheet folds and triangles collapse.
Scene lens_scene(double distance, int pixels) {
  Scene s = straight_down_scene(4.0, distance, 30.0, pixels);
  s.render.fresnel = true;
  return s;
}

struct Case {
  Scene scene;
  std::shared_ptr<const Mesh> mesh;
};

std::map<std::string, Case> cases() {
  std::map<std::string, Case> c;
  c["lens"] = {lens_scene(60.0, 256), lens_mesh()};
  c["lens_far"] = {lens_scene(120.0, 200), lens_mesh()};
  {
    Scene s = lens_scene(50.0, 256);
    s.screen.width = s.screen.height = 40;
    s.light.direction = {std::sin(0.35), 0, -std::cos(0.35)};
    c["oblique_slab"] = {s, shared(grid_mesh(flat_face(10.0), 33, 33))};
    // Lit up to the target's far edge: triangles that overhang it keep the part inside.
    Scene t = straight_down_scene(3.0, 50.0, 40.0, 256);
    t.render.fresnel = true;
    t.light.direction = {std::sin(0.35), 0, -std::cos(0.35)};
    c["oblique_slab64"] = {t, shared(grid_mesh(flat_face(10.0), 64, 64))};
  }
  {
    Scene s = lens_scene(60.0, 256);
    s.light.type = LightType::point;
    s.light.position = {2, 1, 200};
    s.light.point_model = PointModel::exact;
    c["point_exact"] = {s, lens_mesh()};
    s.light.point_model = PointModel::approximate;
    c["point_approximate"] = {s, lens_mesh()};
  }
  {
    Scene s = lens_scene(60.0, 256);
    s.render.intensity = IntensityMode::report;
    c["report"] = {s, lens_mesh()};
  }
  {
    Scene s = lens_scene(40.0, 256);
    s.object.material = Material::reflective;
    s.light.direction = glm::normalize(glm::dvec3(0.3, 0, 1));  // from below, onto the curved face
    s.screen.center = {0, 0, -60};
    c["mirror"] = {s, lens_mesh()};
  }
  {
    // A floor and a wall: corners parted between surfaces go to points.
    Scene s = lens_scene(60.0, 256);
    s.light.direction = glm::normalize(glm::dvec3(0.4, 0, -1));
    ScreenParams floor = s.screen, wall = s.screen;
    floor.center = {20, 0, -60};
    wall.center = {22, 0, -40};
    wall.normal = {-1, 0, 0};
    wall.up = {0, 0, 1};
    wall.height = 40;
    s.receivers = {floor, wall};
    s.screen.center = {0, 300, -60};
    c["receivers"] = {s, lens_mesh()};
  }
  {
    Mesh m = grid_mesh(plano_convex_lens(40.0, 10.0), 33, 33);
    m.colours.resize(m.positions.size());
    for (std::size_t i = 0; i < m.colours.size(); ++i)
      m.colours[i] = {0.2f + 0.8f * static_cast<float>(i % 7) / 6.0f, 1.0f, 0.5f};
    c["tinted"] = {lens_scene(60.0, 256), shared(std::move(m))};
  }
  {
    Scene s = lens_scene(60.0, 128);
    s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
    s.object.ior = s.object.glass->index(optics::kLineD);
    s.render.wavelengths = 4;
    c["spectral"] = {s, lens_mesh()};
  }
  {
    Scene s = straight_down_scene(0.0, 40.0, 12.0, 256);
    s.object.flat_face_offset.reset();
    s.object.shape = Shape::solid;
    s.object.ior = 1.5;
    s.render.light_grid = 96;
    s.render.fresnel = true;
    c["solid"] = {s, shared(biconvex_lens(50.0, 50.0, 4.0, 5.0, 49))};
  }
  {
    water::WaveParams p;
    p.grid = 64;
    p.rain_rate = 40;
    p.drop_radius = 0.06;
    p.seed = 3;
    water::WaveSolver solver(p);
    for (int i = 0; i < 200; ++i) solver.step();
    Scene s = straight_down_scene(0.0, 1.2, 2.4, 256);
    s.object.flat_face_offset.reset();
    s.object.shape = Shape::surface;
    s.object.ior = 1.333;
    s.light.direction = glm::normalize(glm::dvec3(0.342, 0, -0.94));
    s.screen.center = {0.4, 0, -1.2};
    s.render.fresnel = true;
    c["water"] = {s, shared(water::water_mesh(solver))};
  }
  return c;
}

double sum(const std::vector<float>& v) {
  double total = 0;
  for (float x : v) total += x;
  return total;
}

}  // namespace

class TriangleSetups : public GlTest {
 protected:
  std::pair<RgbHdrImage, FrameStats> draw(const Case& c, TriangleSetup setup) {
    engine_->set_triangle_setup(setup);
    RgbHdrImage img = render_rgb(c.scene, c.mesh);
    return {std::move(img), engine_->stats()};
  }
};

TEST_F(TriangleSetups, TheCpuAndTheGeometryStageDrawTheSamePicture) {
  for (const auto& [name, c] : cases()) {
    SCOPED_TRACE(name);
    const auto [gpu, gpu_stats] = draw(c, TriangleSetup::gpu);
    const auto [cpu, cpu_stats] = draw(c, TriangleSetup::cpu);
    EXPECT_FALSE(gpu_stats.cpu_setup);
    EXPECT_TRUE(cpu_stats.cpu_setup);
    ASSERT_EQ(gpu.pixels.size(), cpu.pixels.size());
    const double total = sum(gpu.pixels);
    ASSERT_GT(total, 0.0);
    // Single precision on the GL against double on the CPU: the flux of a
    // triangle a few pixels wide (a small solid angle, a difference of
    // areas) is good to ~1e-4 in floats, and "report" divides two such
    // areas of the tiniest triangles near the focus.
    const double tolerance = c.scene.render.intensity == IntensityMode::report ? 5e-3 : 1e-4;
    EXPECT_NEAR(sum(cpu.pixels), total, tolerance * total);
    // Corners moved by ~1e-4 pixel shift light between neighbours by that
    // small a share.
    double differ = 0;
    for (std::size_t i = 0; i < gpu.pixels.size(); ++i) differ += std::abs(gpu.pixels[i] - cpu.pixels[i]);
    EXPECT_LT(differ, 10 * tolerance * total);
    EXPECT_EQ(cpu_stats.drawn, gpu_stats.drawn);
    EXPECT_EQ(cpu_stats.dropped, gpu_stats.dropped);
    EXPECT_NEAR(cpu_stats.folded, gpu_stats.folded, 2 + 1e-3 * gpu_stats.drawn);
    EXPECT_NEAR(cpu_stats.collapsed, gpu_stats.collapsed, 2 + 1e-3 * gpu_stats.drawn);
  }
}

TEST_F(TriangleSetups, AutomaticMeansTheCpuUnderASoftwareRenderer) {
  const Case c = cases().at("lens");
  const bool software = context_->renderer().find("llvmpipe") != std::string::npos ||
                        context_->renderer().find("softpipe") != std::string::npos;
  EXPECT_EQ(draw(c, TriangleSetup::automatic).second.cpu_setup, software);
}
