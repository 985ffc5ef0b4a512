// SPDX-License-Identifier: LGPL-2.1-or-later
// render.fidelity "auto": the choice rule on hand-made calibrations, the
// calibration file's checks, and the physics case: a far directional light
// on a lens needs fewer vertices than a point light imaged on the screen,
// and both choices meet the target against a fresh reference.
#include "gl_test_support.hpp"

#include "caustic/calibrate.hpp"
#include "caustic/fidelity.hpp"
#include "caustic/fnv1a.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"
#include "caustic/resample.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

using namespace caustic;
using namespace caustic::testing;

namespace {

// Levels whose meshes only need their vertex counts (for the cost order).
MeshLevels fake_levels(std::initializer_list<int> grids, std::size_t source_vertices) {
  auto mesh_of = [](std::size_t n) {
    Mesh m;
    m.positions.resize(n);
    return std::make_shared<const Mesh>(std::move(m));
  };
  MeshLevels levels;
  levels.source = mesh_of(source_vertices);
  for (int n : grids) levels.resampled[n] = mesh_of(static_cast<std::size_t>(n) * n);
  return levels;
}

CalibrationEntry entry(int resolution, std::size_t vertices, PointModel model, bool fresnel, double l1) {
  CalibrationEntry e;
  e.config = {resolution, model, fresnel};
  e.vertices = vertices;
  e.relative_l1 = l1;
  return e;
}

Calibration hand_made() {
  Calibration c;
  c.fingerprint = "f";
  c.entries = {entry(0, 65536, PointModel::exact, true, 0.001),
               entry(16, 256, PointModel::exact, true, 0.08),
               entry(32, 1024, PointModel::exact, true, 0.02),
               entry(32, 1024, PointModel::approximate, true, 0.04),
               entry(32, 1024, PointModel::exact, false, 0.03),
               entry(64, 4096, PointModel::approximate, false, 0.001),
               entry(512, 262144, PointModel::exact, true, 0.0001)};  // a level the scene does not offer
  return c;
}

}  // namespace

TEST(FidelityChoice, CheapestMeetingTheTargetInCostOrder) {
  const MeshLevels levels = fake_levels({16, 32, 64}, 65536);
  const Calibration c = hand_made();
  // 5%: 32^2 is the fewest vertices that qualify; among the three at 32^2 the
  // approximate model (with Fresnel) is cheaper than the exact ones.
  FidelityChoice choice = choose_fidelity(c, 0.05, levels);
  EXPECT_EQ(choice.config, (FidelityConfig{32, PointModel::approximate, true}));
  EXPECT_DOUBLE_EQ(*choice.expected_l1, 0.04);
  EXPECT_TRUE(choice.meets_target);
  // 2.5%: only exact/Fresnel qualifies at 32^2.
  choice = choose_fidelity(c, 0.025, levels);
  EXPECT_EQ(choice.config, (FidelityConfig{32, PointModel::exact, true}));
  // 0.5%: 64^2 (approximate, no Fresnel) beats the mesh as loaded on vertices.
  EXPECT_EQ(choose_fidelity(c, 0.005, levels).config, (FidelityConfig{64, PointModel::approximate, false}));
  // Nothing offered meets 0.01%: the most accurate offered (not the 512^2 row).
  choice = choose_fidelity(c, 0.0001, levels);
  EXPECT_FALSE(choice.meets_target);
  EXPECT_EQ(choice.config.mesh_resolution, 0);
  EXPECT_DOUBLE_EQ(*choice.expected_l1, 0.001);
  // Measured at the streamed size, 32^2 shows facets (9% off the full
  // model there): 5% now takes 64^2, the cheapest that meets both.
  Calibration streamed = c;
  for (auto& e : streamed.entries) {
    e.streamed_l1 = e.config.mesh_resolution == 32 ? 0.09 : 0.01;
    e.streamed_ssim = 0.99;
  }
  EXPECT_EQ(choose_fidelity(streamed, 0.05, levels).config.mesh_resolution, 64);
  // A structural error (1 - SSIM) counts as well.
  for (auto& e : streamed.entries) e.streamed_l1 = 0.01, e.streamed_ssim = e.config.mesh_resolution == 64 ? 0.9 : 0.99;
  EXPECT_EQ(choose_fidelity(streamed, 0.05, levels).config.mesh_resolution, 32);
  EXPECT_FALSE(meets_target(streamed.entries.front(), 0.001));
  // No calibration: the full model, no expected error.
  choice = choose_fidelity(std::nullopt, 0.05, levels);
  EXPECT_EQ(choice.config, (FidelityConfig{0, PointModel::exact, true}));
  EXPECT_FALSE(choice.expected_l1);
}

TEST(FidelityChoice, ResolveWritesAutoAndLeavesManualAlone) {
  Scene s;
  s.light.point_model = PointModel::exact;
  FidelityChoice choice;
  choice.config = {32, PointModel::approximate, false};
  const Scene automatic = resolve_fidelity(s, choice);
  EXPECT_EQ(automatic.render.mesh_resolution, 32);
  EXPECT_EQ(automatic.light.point_model, PointModel::approximate);
  EXPECT_FALSE(automatic.render.fresnel);
  s.render.fidelity = Fidelity::manual;
  EXPECT_EQ(resolve_fidelity(s, choice), s);
}

TEST(FidelityChoice, ASolidTakesTheCoarsestLightGridThatMeetsTheTarget) {
  // A solid is offered as loaded only; its calibration varies the light grid.
  const MeshLevels levels = fake_levels({}, 133120);
  Calibration c;
  c.fingerprint = "f";
  for (const auto& [grid, l1] : {std::pair{64, 0.06}, std::pair{128, 0.02}, std::pair{256, 0.004}}) {
    CalibrationEntry e = entry(0, 133120, PointModel::exact, true, l1);
    e.config.light_grid = grid;
    c.entries.push_back(e);
  }
  EXPECT_EQ(choose_fidelity(c, 0.05, levels).config.light_grid, 128);
  EXPECT_EQ(choose_fidelity(c, 0.01, levels).config.light_grid, 256);
  // Never above the scene's own grid, even where only a finer one meets the
  // target (a calibration made when the scene's grid was finer).
  EXPECT_EQ(choose_fidelity(c, 0.01, levels, 128).config.light_grid, 128);
  EXPECT_FALSE(choose_fidelity(c, 0.01, levels, 128).meets_target);
  const Calibration back = calibration_from_json(nlohmann::json::parse(calibration_to_json(c).dump()));
  EXPECT_EQ(back.entries[1].config, c.entries[1].config);

  Scene solid;
  solid.object.shape = Shape::solid;
  const Scene chosen = resolve_fidelity(solid, choose_fidelity(c, 0.05, levels));
  EXPECT_EQ(chosen.render.light_grid, 128);
  // Uncalibrated, or a slab: the scene's own grid stays.
  EXPECT_EQ(resolve_fidelity(solid, choose_fidelity(std::nullopt, 0.05, levels)).render.light_grid, 256);
  EXPECT_EQ(resolve_fidelity(Scene{}, choose_fidelity(c, 0.05, levels)).render.light_grid, 256);
  // Written while auto decides it: overridden, and said so; on a slab it is moot instead.
  const nlohmann::json written = {{"render", {{"light_grid", 512}}}};
  ASSERT_EQ(fidelity_overrides(written, solid).size(), 1u);
  EXPECT_EQ(fidelity_overrides(written, solid)[0].first, "render.light_grid");
  EXPECT_TRUE(fidelity_overrides(written, Scene{}).empty());
  // A light grid outside the scene format's range is refused by name.
  nlohmann::json bad = calibration_to_json(c);
  bad["entries"][0]["light_grid"] = 4;
  try {
    calibration_from_json(bad);
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "entries[0].light_grid");
  }
}

TEST(Calibration, RoundTripsAndNamesWhatIsWrongInAFile) {
  const Calibration c = hand_made();
  const Calibration back = calibration_from_json(nlohmann::json::parse(calibration_to_json(c).dump()));
  ASSERT_EQ(back.entries.size(), c.entries.size());
  EXPECT_EQ(back.entries[3].config, c.entries[3].config);
  EXPECT_DOUBLE_EQ(back.entries[3].relative_l1, 0.04);
  EXPECT_FALSE(back.entries[3].streamed_l1) << "not measured: stays absent";
  Calibration streamed = c;
  streamed.streamed_width = streamed.streamed_height = 1024;
  streamed.entries[3].streamed_l1 = 0.07;
  streamed.entries[3].streamed_ssim = 0.96;
  const Calibration again = calibration_from_json(nlohmann::json::parse(calibration_to_json(streamed).dump()));
  EXPECT_EQ(again.streamed_width, 1024);
  EXPECT_DOUBLE_EQ(*again.entries[3].streamed_l1, 0.07);
  EXPECT_DOUBLE_EQ(*again.entries[3].streamed_ssim, 0.96);
  EXPECT_DOUBLE_EQ(worst_error(again.entries[3]), 0.07);

  auto rejects = [](nlohmann::json j, const std::string& key) {
    try {
      calibration_from_json(j);
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  const nlohmann::json good = calibration_to_json(c);
  nlohmann::json j = good;
  j["format"] = "v0";
  rejects(j, "format");
  j = good;
  j.erase("fingerprint");
  rejects(j, "fingerprint");
  j = good;
  j["entries"] = 3;
  rejects(j, "entries");
  j = good;
  j["entries"][1]["point_model"] = "guess";
  rejects(j, "entries[1].point_model");
  j = good;
  j["entries"][2]["relative_l1"] = -1;
  rejects(j, "entries[2].relative_l1");
  j["entries"][2]["relative_l1"] = 1e308;  // once printed as "expected relative L1 inf%"
  rejects(j, "entries[2].relative_l1");
  j["entries"][2]["relative_l1"] = 0.04;
  for (const int resolution : {-5, 1, 100000}) {  // once matched no level, without a word
    j["entries"][2]["mesh_resolution"] = resolution;
    rejects(j, "entries[2].mesh_resolution");
  }
  j = good;
  j["entries"][0]["fresnel"] = "yes";
  rejects(j, "entries[0].fresnel");
  // Whole numbers in range: 2.7 was read as 2, -5 vertices as 18
  // quintillion, a width of 1e30 as whatever the conversion made of it.
  for (const auto& [where, key, value] :
       {std::tuple{"entries", "mesh_resolution", nlohmann::json(2.7)}, std::tuple{"entries", "vertices", nlohmann::json(-5)},
        std::tuple{"", "reference_photons", nlohmann::json(-1)}, std::tuple{"", "width", nlohmann::json(1e30)},
        std::tuple{"", "height", nlohmann::json(4294967296LL)}}) {
    j = good;
    (std::string(where).empty() ? j : j["entries"][0])[key] = value;
    rejects(j, std::string(where).empty() ? key : std::string("entries[0].") + key);
  }

  const auto dir = std::filesystem::temp_directory_path() / "causticd_fidelity_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "c.json") << good.dump();
  EXPECT_TRUE(load_calibration(dir / "c.json", "f"));
  EXPECT_FALSE(load_calibration(dir / "c.json", "another scene"));
  EXPECT_FALSE(load_calibration(dir / "missing.json", "f"));
  std::ofstream(dir / "bad.json") << "{\"format\": ";
  EXPECT_THROW(load_calibration(dir / "bad.json", "f"), SceneError);
  // Read as every outside JSON text is: what follows a NUL is not ignored.
  {
    std::ofstream out(dir / "nul.json", std::ios::binary);
    out << good.dump() << '\0' << "junk";
  }
  try {
    load_calibration(dir / "nul.json", "f");
    ADD_FAILURE() << "a calibration with a NUL inside was read";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("nul.json is not valid JSON"), std::string::npos) << e.what();
  }
  // A file larger than its bound is refused there, not read whole.
  {
    std::ofstream(dir / "big.json") << std::string((1 << 20) + 10, ' ');
  }
  try {
    load_calibration(dir / "big.json", "f");
    ADD_FAILURE() << "a 1 MiB file was read as a calibration";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("larger than 1024 KiB"), std::string::npos) << e.what();
  }
  // A device is not opened (/dev/zero was read to the bound).
  try {
    load_calibration("/dev/zero", "f");
    ADD_FAILURE() << "/dev/zero was read as a calibration";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("device or kernel file, not a calibration file"), std::string::npos) << e.what();
  }
  // Beside its scene, found without being named: a pipe there held render
  // up, a folder read as broken JSON.
  ASSERT_EQ(::mkfifo((dir / "pipe.json").c_str(), 0600), 0);
  for (const char* name : {"pipe.json", "."}) {
    try {
      load_calibration(dir / name, "f");
      ADD_FAILURE() << name << " was read as a calibration";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("is a folder, pipe, socket, device"), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(Fnv1a, GivesThePublishedTestVectors) {
  // The FNV authors' test suite (isthe.com/chongo/tech/comp/fnv): the empty
  // string is the offset basis itself.
  EXPECT_EQ(caustic::fnv1a(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(caustic::fnv1a("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(caustic::fnv1a("foobar"), 0x85944171f73967e8ull);
}

TEST(Calibration, FingerprintFollowsThePhysicsNotTheChoices) {
  const Mesh mesh = grid_mesh(plano_convex_lens(40.0, 10.0), 16, 16);
  Scene s;
  const std::string base = scene_fingerprint(s, mesh);
  Scene same = s;
  same.post.exposure = 3;
  same.render.width = 64;
  same.render.mesh_resolution = 32;
  same.render.fresnel = false;
  same.light.point_model = PointModel::approximate;
  same.render.accuracy_target = 0.2;
  EXPECT_EQ(scene_fingerprint(same, mesh), base);
  Scene moved = s;
  moved.light.direction = glm::normalize(glm::dvec3(0.1, 0, -1));
  EXPECT_NE(scene_fingerprint(moved, mesh), base);
  Scene glass = s;
  glass.object.ior = 1.6;
  EXPECT_NE(scene_fingerprint(glass, mesh), base);
  EXPECT_NE(scene_fingerprint(s, grid_mesh(plano_convex_lens(41.0, 10.0), 16, 16)), base);
  // Two vertices moved by +1 mm and -1 mm along the same axis: a weighted
  // sum of the positions stays as it was, the mesh does not (nor does a
  // designed face, whose heights sum to about 0, under any such edit).
  for (int axis = 0; axis < 3; ++axis) {
    Mesh edited = mesh;
    edited.positions[10][axis] += 1.0f;
    edited.positions[200][axis] -= 1.0f;
    EXPECT_NE(scene_fingerprint(s, edited), base) << "axis " << axis;
  }
  Mesh rewired = mesh;  // the same corners, one triangle turned round
  std::swap(rewired.triangles[5][0], rewired.triangles[5][1]);
  EXPECT_NE(scene_fingerprint(s, rewired), base);
}

TEST(MeshLevels, EveryLevelSitsWhereTheLoadedMeshDoes) {
  // A coarse level misses a spike of the loaded mesh, so its own bounds
  // differ. Placed by them (fit_size centres), it sat elsewhere, its flat
  // face above the public box, and the render refused screens the public
  // box had passed: a refusal seen only as a frame not drawn, which told
  // the level's hidden height.
  Mesh spiked = grid_mesh(plano_convex_lens(40.0, 10.0), 65, 65);
  spiked.positions[65 * 20 + 21].z += 5.0f;  // between the coarse grids' vertices
  const auto source = shared(std::move(spiked));
  const MeshLevels levels = build_mesh_levels(source, {0, 0, 1}, {8, 16, 32});
  Scene s;
  s.mesh = "generated";
  s.object.fit_size = 100.0;
  s.object.rotation_deg = {30, 0, 0};
  s.object.flat_face_offset = levels.bounds->hi.z + 0.5;
  const Placement placed = levels.place(s.object);
  double lowest = 1e300, highest = -1e300;
  for (const auto& corner : placed.box) {
    lowest = std::min(lowest, corner.z);
    highest = std::max(highest, corner.z);
  }
  for (const int n : {0, 8, 16, 32})
    for (const double z : {lowest - 1e-6, highest + 1e-6}) {  // a screen touching the box below it, and above
      Scene at = s;
      at.render.mesh_resolution = n;
      at.screen.center = {0, 0, z};
      EXPECT_NO_THROW(check_geometry_public(at, levels)) << n << " " << z;
      EXPECT_NO_THROW(check_geometry(at, levels)) << "level " << n << ", screen at " << z;
    }
}

class FidelityAuto : public GlTest {};

TEST_F(FidelityAuto, CheaperForAFarDirectionalLightThanAPointLightImagedOnTheScreen) {
  const auto source = shared(grid_mesh(plano_convex_lens(40.0, 10.0), 256, 256));
  const MeshLevels levels = build_mesh_levels(source, {0, 0, 1}, coarser_resolutions(*source, Scene{}));
  Scene lens;
  lens.mesh = "generated";
  lens.object.flat_face_offset = 4.0;
  lens.render.width = lens.render.height = 256;
  // Far directional light, screen half-way to the focus: a smooth disc.
  Scene far = lens;
  far.screen.center = {0, 0, -40};
  far.screen.width = far.screen.height = 24;
  // Point light 200 mm above: 1/v = 1/80 - 1/200 puts its image 133 mm below.
  Scene near = lens;
  near.light.type = LightType::point;
  near.light.position = {0, 0, 200};
  near.screen.center = {0, 0, -133};
  near.screen.width = near.screen.height = 6;

  CalibrateOptions options;
  options.photons = 4'000'000;
  options.max_side = 256;
  options.frames = 1;
  struct Outcome {
    FidelityChoice choice;
    std::size_t vertices;
    double l1;
  };
  auto run = [&](const Scene& scene) {
    const Calibration c = calibrate(scene, levels, *engine_, context_->renderer(), options);
    Outcome o{choose_fidelity(c, 0.05, levels), 0, 0};
    EXPECT_TRUE(o.choice.meets_target);
    o.vertices = levels.vertices(o.choice.config.mesh_resolution);
    // Judged against a reference the calibration never saw (another seed, twice the photons).
    ReferenceOptions fresh;
    fresh.photons = 8'000'000;
    fresh.seed = 7;
    const HdrImage truth = trace_reference(scene, *source, fresh).image;
    const Scene chosen = resolve_fidelity(scene, o.choice);
    const HdrImage image = render(chosen, levels.at(chosen.render.mesh_resolution));
    o.l1 = compare(box_down(image, 4), box_down(truth, 4)).relative_l1;
    std::printf("choice: mesh %d (%zu vertices), %s, Fresnel %d: expected L1 %.4f, measured %.4f\n",
                o.choice.config.mesh_resolution, o.vertices,
                o.choice.config.point_model == PointModel::exact ? "exact" : "approximate", o.choice.config.fresnel,
                *o.choice.expected_l1, o.l1);
    return o;
  };
  const Outcome f = run(far), n = run(near);
  EXPECT_LT(f.vertices, n.vertices);
  EXPECT_LE(f.l1, 0.05);
  EXPECT_LE(n.l1, 0.05);
  // Both sit on Fresnel: leaving it out costs 8% of the flux at n = 1.5.
  EXPECT_TRUE(f.choice.config.fresnel);
  EXPECT_TRUE(n.choice.config.fresnel);
  // The report's entry-point approximation is off by more than 5% this close.
  EXPECT_EQ(n.choice.config.point_model, PointModel::exact);
}
