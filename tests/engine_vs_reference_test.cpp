// The GL engine against the independent photon tracer on every built-in
// scene at a fixed configuration (128x128 pixels, the scenes' 256x256-vertex
// meshes, 16 M photons). The bounds are justified in docs/accuracy.md.
#include "gl_test_support.hpp"

#include "caustic/reference.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

using namespace caustic;
using namespace caustic::testing;

namespace {

double relative_l1(const HdrImage& a, const HdrImage& b) {
  double diff = 0, sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    diff += std::abs(a.pixels[i] - b.pixels[i]);
    sum += std::abs(b.pixels[i]);
  }
  return diff / sum;
}

struct Case {
  const char* scene;
  double bound;
};

class EngineVsReference : public GlTest, public ::testing::WithParamInterface<Case> {};

}  // namespace

TEST_P(EngineVsReference, RelativeL1WithinTheStatedBound) {
  const Case c = GetParam();
  Scene scene = load_scene(std::string(CAUSTIC_ASSET_DIR) + "/scenes/" + c.scene + ".json");
  scene.render.width = scene.render.height = 128;
  const auto mesh = shared(load_obj(scene.mesh_path()));
  const HdrImage engine = render(scene, mesh);
  ReferenceOptions options;
  options.photons = 16'000'000;
  const ReferenceResult reference = trace_reference(scene, *mesh, options);
  const double l1 = relative_l1(engine, reference.image);
  std::printf("%s: relative L1 engine vs reference %.4f (bound %.3f)\n", c.scene, l1, c.bound);
  EXPECT_LT(l1, c.bound);
}

INSTANTIATE_TEST_SUITE_P(BuiltInScenes, EngineVsReference,
                         ::testing::Values(Case{"slab", 0.01}, Case{"wavy", 0.01}, Case{"cylinder", 0.03},
                                           Case{"lens", 0.01}),
                         [](const auto& info) { return std::string(info.param.scene); });

TEST_F(EngineVsReference, ReportIntensityIsFarFromTheReferenceWhereEnergyIsNot) {
  // The lens half-way to its focus: the beam converges, and the report's
  // area ratio measures that convergence rather than the light it carries.
  Scene scene = load_scene(std::string(CAUSTIC_ASSET_DIR) + "/scenes/lens.json");
  scene = apply_merge_patch(scene, nlohmann::json{{"focus_distance", 40}, {"render", {{"width", 128}, {"height", 128}}},
                                    {"screen", {{"width", 16}, {"height", 16}}}});
  const auto mesh = shared(load_obj(scene.mesh_path()));
  ReferenceOptions options;
  options.photons = 16'000'000;
  const HdrImage reference = trace_reference(scene, *mesh, options).image;
  const double energy = relative_l1(render(scene, mesh), reference);
  scene.render.intensity = IntensityMode::report;
  const double report = relative_l1(render(scene, mesh), reference);
  std::printf("lens at 40 mm: relative L1 against the reference: energy %.4f, report %.4f\n", energy, report);
  EXPECT_LT(energy, 0.01);
  EXPECT_GT(report, 10 * energy);
}
