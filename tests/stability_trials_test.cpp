// SPDX-License-Identifier: LGPL-2.1-or-later
// Randomised stability trials (fixed seeds): poses, lights and indices that
// include TIR, grazing incidence, a point light almost on the flat face, a
// screen almost touching the object, indices from 1.0001 to 4, and
// degenerate meshes. For the engine and the reference tracer alike: never
// NaN/Inf, never a crash, never more flux than entered, and every rejected
// scene rejected with a message that names a key.
#include "gl_test_support.hpp"

#include "caustic/reference.hpp"

#include <nlohmann/json.hpp>

#include <random>

using namespace caustic;
using namespace caustic::testing;

namespace {

struct Trial {
  Scene scene;
  std::shared_ptr<const Mesh> mesh;
};

Mesh random_mesh(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int kind = static_cast<int>(u(rng) * 4);
  const int n = 6 + static_cast<int>(u(rng) * 10);
  Mesh m = kind == 0   ? grid_mesh(plano_convex_lens(10 + 40 * u(rng), 5.0), n, n)
           : kind == 1 ? grid_mesh(sine_window(0.5 * u(rng), 3 * u(rng), 0.5 * u(rng), 3 * u(rng), 5.0), n, n)
           : kind == 2 ? grid_mesh(cylindrical_lens(8 + 30 * u(rng), 5.0), n, n)
                       : grid_mesh(flat_face(5.0), n, n);
  if (u(rng) < 0.2) {  // degenerate: collapsed and repeated triangles
    m.triangles.push_back({0, 0, 0});
    m.triangles.push_back({1, 1, 2});
    m.positions[3] = m.positions[4];
  }
  return m;
}

Trial random_trial(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Trial t;
  t.mesh = shared(random_mesh(rng));
  Scene& s = t.scene;
  s.mesh = "generated";
  s.object.flat_face_offset = 3.0;
  const double iors[] = {1.0001, 1.33, 1.5, 2.4, 4.0};
  s.object.ior = iors[static_cast<int>(u(rng) * 5)];
  s.object.material = u(rng) < 0.15 ? Material::reflective : Material::refractive;
  s.object.rotation_deg = {120 * (u(rng) - 0.5), 120 * (u(rng) - 0.5), 360 * u(rng)};
  s.render.fresnel = u(rng) < 0.5;
  s.render.width = s.render.height = 48;
  // Light from anywhere in the upper hemisphere, grazing included.
  const double tilt = 1.5707 * std::sqrt(u(rng)), azimuth = 6.2832 * u(rng);
  const glm::dvec3 dir(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), -std::cos(tilt));
  if (u(rng) < 0.4) {
    s.light.type = LightType::point;
    s.light.point_model = u(rng) < 0.5 ? PointModel::exact : PointModel::approximate;
    // Sometimes almost on the flat face (1e-4 above it).
    s.light.position = u(rng) < 0.2 ? glm::dvec3(4 * u(rng), 4 * u(rng), 3.0001) : -dir * (5 + 80 * u(rng));
  } else {
    s.light.direction = dir;
  }
  // Sometimes almost touching the object.
  const double gap = u(rng) < 0.2 ? 1e-3 : 1 + 60 * u(rng);
  s.screen.center = {0, 0, -gap};
  s.screen.width = s.screen.height = 5 + 60 * u(rng);
  return t;
}

}  // namespace

class StabilityTrials : public GlTest {};

TEST_F(StabilityTrials, EngineAndReferenceStayFiniteAndCreateNoEnergy) {
  std::mt19937 rng(20261122);
  int rendered = 0, rejected = 0;
  double worst_excess = -1;
  int reference_refused = 0;
  for (int i = 0; i < 3000; ++i) {
    Trial t = random_trial(rng);
    const Placement placement = place_object(t.scene.object, *t.mesh);
    try {
      check_geometry(t.scene, *t.mesh, placement);
    } catch (const SceneError& e) {
      ++rejected;
      EXPECT_FALSE(e.key().empty()) << e.what();
      EXPECT_THROW(engine_->set_scene(t.scene, t.mesh), SceneError);
      continue;
    }
    const HdrImage img = render(t.scene, t.mesh);
    ASSERT_TRUE(all_finite(img)) << "trial " << i;
    // What entered the triangles that reached the screen bounds what lands.
    const FluxSummary entering = summarize_flux(t.scene, *t.mesh, placement);
    // float32 on the GPU against double on the CPU: in ordinary poses the two
    // agree to 2e-5 (engine_energy_test); grazing entry at IOR up to 4 has
    // shown up to 2e-3, so the bound here is 5e-3.
    const double landed = total_flux(img, t.scene.screen);
    worst_excess = std::max(worst_excess, (landed - entering.flux) / std::max(entering.flux, 1e-12));
    EXPECT_LE(landed, entering.flux * (1 + 5e-3) + 1e-9)
        << "trial " << i << ": " << scene_to_json(t.scene).dump() << " drawn " << engine_->stats().drawn << "/"
        << entering.valid_triangles;
    if (i % 10 == 0) {  // the reference on a tenth of them: it is slower
      ReferenceOptions options;
      options.photons = 4096;
      try {
        const ReferenceResult r = trace_reference(t.scene, *t.mesh, options);
        for (float v : r.image.pixels) ASSERT_TRUE(std::isfinite(v) && v >= 0) << "trial " << i;
      } catch (const SceneError& e) {
        // The tracer cannot launch from a point light beside a wide object; it says so.
        EXPECT_EQ(e.key(), "light.position") << e.what();
        ++reference_refused;
      }
    }
    ++rendered;
  }
  std::printf("%d trials rendered, %d rejected with a named key; largest flux excess %.1e; the reference refused %d\n",
              rendered, rejected, worst_excess, reference_refused);
  EXPECT_GT(rendered, 2000);
}
