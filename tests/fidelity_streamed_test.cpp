// SPDX-License-Identifier: LGPL-2.1-or-later
// Fidelity "auto" judged where it is seen: for every shipped scene, the
// configuration its calibration picks, rendered at the streamed size (the
// scene's render size), against the full model at that size (no box filter,
// so facets count: relative L1 and 1 - SSIM of the tone-mapped pictures) and
// against a reference the calibration never saw (another seed). Both meet
// the scene's target. Before the streamed terms the wavy window's choice,
// 64^2, was 14% off the full model at 1024^2 and visibly faceted.
#include "gl_test_support.hpp"

#include "caustic/exposure.hpp"
#include "caustic/fidelity.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"
#include "caustic/resample.hpp"
#include "caustic/screen_follow.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

using namespace caustic;
using namespace caustic::testing;

class StreamedFidelity : public GlTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(StreamedFidelity, TheChoiceMeetsTheTargetAtTheStreamedSize) {
  const std::filesystem::path file = std::string(CAUSTIC_ASSET_DIR) + "/scenes/" + GetParam() + ".json";
  if (GetParam().rfind("design-", 0) == 0 && !std::filesystem::exists(file))
    GTEST_SKIP() << GetParam() << " was not built";
  const Scene loaded = load_scene(file);
  const auto source = std::make_shared<const Mesh>(load_obj(loaded.mesh_path()));
  const MeshLevels levels = build_mesh_levels(source, loaded.object.flat_face_normal, coarser_resolutions(*source, loaded));
  const Scene scene = follow_light(loaded, levels.place(loaded.object));  // as a session renders it
  const auto calibration = load_calibration(calibration_path(file), scene_fingerprint(scene, *source));
  ASSERT_TRUE(calibration) << "no calibration for the scene as shipped";
  ASSERT_EQ(calibration->streamed_width, scene.render.width);
  const double target = scene.render.accuracy_target;
  const FidelityChoice choice = choose_fidelity(calibration, target, levels);
  EXPECT_TRUE(choice.meets_target);
  const Scene chosen = resolve_fidelity(scene, choice);

  // At the streamed size, against the full model.
  Scene full = scene;
  full.render.mesh_resolution = 0;
  full.render.fresnel = true;
  full.light.point_model = PointModel::exact;
  const HdrImage truth = render(full, source);
  const HdrImage seen = render(chosen, levels.at(chosen.render.mesh_resolution));
  const ImageError streamed = compare(seen, truth, exposure::settled_exposure(scene.post, truth), scene.post.gamma);
  std::printf("%s: mesh %d, Fresnel %d; at %dx%d against the full model: L1 %.4f, SSIM %.4f\n", GetParam().c_str(),
              chosen.render.mesh_resolution, chosen.render.fresnel, scene.render.width, scene.render.height,
              streamed.relative_l1, streamed.ssim);
  EXPECT_LE(streamed.relative_l1, target);
  EXPECT_LE(1 - streamed.ssim, target);

  // Against the reference, as calibrated (box-filtered at the calibration
  // size), from photons the calibration did not use.
  if (GetParam().rfind("design-", 0) == 0) return;  // the designed scenes check theirs in designed_scenes_test
  Scene small = chosen;
  small.render.width = calibration->width;
  small.render.height = calibration->height;
  Scene small_truth = full;
  small_truth.render.width = calibration->width;
  small_truth.render.height = calibration->height;
  ReferenceOptions fresh;
  fresh.photons = 8'000'000;
  fresh.seed = 11;
  const HdrImage reference = box_down(trace_reference(small_truth, *source, fresh).image, calibration->compare_factor);
  const HdrImage image = box_down(render(small, levels.at(small.render.mesh_resolution)), calibration->compare_factor);
  const double l1 = compare(image, reference).relative_l1;
  std::printf("%s: against a fresh reference at %dx%d / %d: L1 %.4f\n", GetParam().c_str(), calibration->width,
              calibration->height, calibration->compare_factor, l1);
  EXPECT_LE(l1, target);
}

INSTANTIATE_TEST_SUITE_P(Scenes, StreamedFidelity, ::testing::ValuesIn(kShippedScenes), scene_test_name);
