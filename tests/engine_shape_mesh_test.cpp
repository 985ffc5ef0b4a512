// SPDX-License-Identifier: LGPL-2.1-or-later
// A receiver shaped by a scene's mesh: a flat plate of 72 triangles, tilted
// 40 degrees under a flat slab's straight-down light, a floor below. Its
// light drawn in its (u, v) atlas. Oracles: Lambert's cosine law over the
// whole plate, the flux it intercepts (its silhouette times E0), the floor's
// share (the rest, its shadow dark); the photon reference agrees.
#include "gl_test_support.hpp"
#include "reference_l1.hpp"

#include "caustic/receiver_meshes.hpp"
#include "caustic/receivers.hpp"

#include <cmath>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

constexpr double kHalf = 6;                                  // the plate is 12 x 12 mm
const double kTilt = 40.0 * std::numbers::pi / 180.0;         // its normal from the light's

// A 7 x 7 grid of vertices in its own frame (z = 0), its atlas straight across.
Mesh plate() {
  Mesh m;
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) {
      m.positions.emplace_back(-kHalf + 2 * i, -kHalf + 2 * j, 0);
      m.uvs.emplace_back(i / 6.0, j / 6.0);
    }
  for (unsigned j = 0; j < 6; ++j)
    for (unsigned i = 0; i < 6; ++i) {
      const unsigned a = j * 7 + i;
      m.triangles.emplace_back(a, a + 1, a + 8);
      m.triangles.emplace_back(a, a + 8, a + 7);
    }
  m.normals = smooth_normals(m.positions, m.triangles);
  return m;
}

// The plate 30 mm below the slab turned about y.
Scene plate_scene(int pixels) {
  auto table = std::make_shared<ReceiverMeshTable>();
  table->files = {{"plate", "plate.obj"}};
  table->meshes = {{"plate", plate()}};
  ScreenParams p;
  p.center = {0.0123, 0, -30};  // off the rays' grid: no ray exactly on a triangle's edge
  p.normal = {std::sin(kTilt), 0, std::cos(kTilt)};
  p.up = {0, 1, 0};
  p.width = p.height = 1;
  p.shaped = ShapedMesh{"plate", std::make_shared<const ReceiverMesh>(
                                     place_receiver_mesh(table->meshes.at("plate"), p.center, p.normal, p.up))};
  Scene s = over_a_floor(pixels, p);
  s.receiver_meshes = table;
  return s;
}

}  // namespace

class EngineShapeMesh : public GlTest {};

TEST_F(EngineShapeMesh, ThePlateFollowsTheCosineLawAndTheFluxAddsUp) {
  const Scene s = plate_scene(512);
  const HdrImage img = render(s, fine_slab());
  EXPECT_TRUE(engine_->stats().cpu_setup);  // a mesh lands on the CPU whatever the renderer
  const AtlasTile t = atlas_layout(512, 512, 3)[1];
  // Every pixel of the plate's tile but a rim as wide as a ray cell (0.31
  // mm across the light: 9 pixels of u, 7 of v), where cells part with
  // the floor, holds E0 cos(tilt).
  int checked = 0;
  for (int y = t.y + 12; y < t.y + t.height - 12; ++y)
    for (int x = t.x + 12; x < t.x + t.width - 12; ++x, ++checked) {
      const double e = img.pixels[static_cast<std::size_t>(y) * img.width + x];
      if (std::abs(e - std::cos(kTilt)) > 0.01 * std::cos(kTilt)) {
        ADD_FAILURE() << "pixel (" << x - t.x << ", " << y - t.y << ") " << e << ", not " << std::cos(kTilt);
        return;
      }
    }
  EXPECT_GT(checked, 1000);
  // Its silhouette, 12 cos(tilt) x 12 mm, catches E0 = 1 over it: to within
  // the ray cells along its outline that part with the floor.
  const double uv_pixel = 1.0 / (double(t.width) * t.height);
  const double on_plate = tile_sum(img, t) * uv_pixel * (2 * kHalf) * (2 * kHalf);
  EXPECT_NEAR(on_plate, 4 * kHalf * kHalf * std::cos(kTilt), 0.3125 * 4 * 2 * kHalf);
  const AtlasTile f = atlas_layout(512, 512, 3)[2];
  const double on_floor = tile_sum(img, f) * (40.0 / f.width) * (40.0 / f.height);
  EXPECT_NEAR((on_plate + on_floor) / 400.0, 1.0, 1e-4);  // the slab's 20 x 20 mm, every ray somewhere
  // Straight under the plate the floor lies in its shade.
  EXPECT_EQ(img.pixels[static_cast<std::size_t>(f.y + f.height / 2) * img.width + f.x + f.width / 2], 0.0f);
}

TEST_F(EngineShapeMesh, TheReferenceTracerAgrees) {
  Scene s = plate_scene(128);
  s.render.fresnel = true;
  const auto fine = shared(grid_mesh(flat_face(10), 513, 513));
  const HdrImage engine = render(s, fine);
  EXPECT_LT(reference_l1(s, *fine, engine, "tilted plate and floor"), 0.01);
}
