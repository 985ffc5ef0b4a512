// SPDX-License-Identifier: LGPL-2.1-or-later
// The water section: read with its defaults, written back, every key bounded
// and named; water makes its own surface (no mesh needed, a mesh named is
// warned about), is a surface, and cannot be fitted; the time step, when
// left to the bound, is a whole fraction of a 60 Hz frame within it.
#include "refusal.hpp"
#include "caustic/spectral.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace caustic;
using namespace caustic::testing;

namespace {

json pool() { return json{{"water", json::object()}}; }

json pool_with(const std::string& key, json value) {
  json doc = pool();
  doc["water"][key] = std::move(value);
  return doc;
}

}  // namespace

TEST(SceneWater, APoolNeedsNoMeshAndIsASurface) {
  const Scene s = scene_from_json(pool(), ".");
  ASSERT_TRUE(s.water.has_value());
  EXPECT_EQ(*s.water, water::WaveParams{});
  EXPECT_EQ(s.object.shape, Shape::surface);
  EXPECT_TRUE(s.mesh.empty());
  // Without water a mesh is still required.
  expect_rejected(json::object(), "mesh");
  EXPECT_FALSE(scene_from_json(minimal(), ".").water.has_value());
}

TEST(SceneWater, EveryKeyRoundTrips) {
  json doc = pool();
  doc["water"] = {{"grid", 64},          {"size", 3.0},         {"wave_speed", 0.5},  {"damping", 0.1},
                  {"time_step", 0.01},   {"rain_rate", 12.5},   {"rain_strength", 0.004},
                  {"drop_radius", 0.06}, {"seed", 123456789012}, {"warmup_s", 2.5}, {"paused", true}};
  const Scene s = scene_from_json(doc, ".");
  EXPECT_EQ(s.water->grid, 64);
  EXPECT_EQ(s.water->seed, 123456789012u);
  EXPECT_TRUE(s.water->paused);
  const json back = scene_to_json(s);
  for (const auto& [key, value] : doc["water"].items()) EXPECT_EQ(back["water"][key], value) << key;
  EXPECT_EQ(scene_from_json(back, "."), s);
  // A scene without water writes null, which reads back as none.
  EXPECT_TRUE(scene_to_json(scene_from_json(minimal(), "."))["water"].is_null());
}

TEST(SceneWater, BadValuesAreNamed) {
  expect_rejected(pool_with("grid", 8), "water.grid");
  expect_rejected(pool_with("grid", 1024), "water.grid");
  expect_rejected(pool_with("grid", 64.5), "water.grid");
  expect_rejected(pool_with("size", 0), "water.size");
  expect_rejected(pool_with("wave_speed", 0), "water.wave_speed");
  expect_rejected(pool_with("damping", -1), "water.damping");
  expect_rejected(pool_with("rain_rate", 1000), "water.rain_rate");
  expect_rejected(pool_with("rain_strength", "deep"), "water.rain_strength");
  expect_rejected(pool_with("seed", 1.5), "water.seed");
  expect_rejected(pool_with("seed", -1), "water.seed");
  try {  // the message quotes the number as written
    scene_from_json(pool_with("seed", 9007199254740993ull), ".");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "water.seed");
    EXPECT_NE(std::string(e.what()).find("got 9007199254740993"), std::string::npos) << e.what();
  }
  EXPECT_EQ(scene_from_json(pool_with("seed", 9007199254740992ull), ".").water->seed, 9007199254740992ull);
  expect_rejected(pool_with("warmup_s", 600), "water.warmup_s");
  expect_rejected(pool_with("paused", 1), "water.paused");
  expect_rejected(pool_with("tide", 1), "water.tide");
  // Rain needs drops the grid resolves.
  json coarse = pool_with("grid", 16);
  coarse["water"]["rain_rate"] = 5;
  expect_rejected(coarse, "water.drop_radius");
  json section = pool();
  section["water"] = 5;
  expect_rejected(section, "water");
}

TEST(SceneWater, WaterThatWouldCostTooMuchWorkIsRefused) {
  // A 10 us step on the finest grid once asked 85 s of solver work for
  // each frame of a stream, and a minute of its warm-up hours before the
  // first: grid² / step cell updates a second are bounded (2^26), and the
  // warm-up's (2^29).
  const auto refused = [](const json& doc) {
    return caustic::testing::refusal<SceneError>([&] { scene_from_json(doc, "."); });
  };
  json fine = pool_with("grid", 512);
  fine["water"]["time_step"] = 1e-5;
  EXPECT_EQ(refused(fine).rfind("water.time_step: a second of this water is", 0), 0u) << refused(fine);
  // The finest grid at its own step streams; a minute of warm-up there is
  // refused, with the longest it may have.
  json finest = pool_with("grid", 512);
  EXPECT_EQ(refused(finest), "accepted");
  finest["water"]["warmup_s"] = 60;
  EXPECT_EQ(refused(finest).rfind("water.warmup_s: must be at most 11.3", 0), 0u) << refused(finest);
  finest["water"]["warmup_s"] = 11;
  EXPECT_EQ(refused(finest), "accepted");
  // Fast waves on the finest grid: a step too short for the budget, named by
  // the wave speed that sets it, which a session may change (the grid, named
  // before, is fixed there).
  json fast = pool_with("grid", 512);
  fast["water"]["wave_speed"] = 2.0;
  EXPECT_EQ(refused(fast).rfind("water.wave_speed: ", 0), 0u) << refused(fast);
}

TEST(SceneWater, ATimeStepBeyondTheBoundIsRefusedWithTheBound) {
  water::WaveParams p;
  const double bound = water::max_time_step(p);
  try {
    scene_from_json(pool_with("time_step", 1.01 * bound), ".");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "water.time_step");
    EXPECT_NE(std::string(e.what()).find("at most 0.0"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(scene_from_json(pool_with("time_step", bound), "."));
}

TEST(SceneWater, TheBoundPicksAWholeFractionOfASixtiethWithinIt) {
  for (int grid : {16, 128, 256, 512}) {
    water::WaveParams p;
    p.grid = grid;
    const double dt = water::step_seconds(p);
    EXPECT_LE(dt, water::max_time_step(p)) << grid;
    const double k = 1.0 / (60 * dt);  // steps per sixtieth of a second
    EXPECT_NEAR(k, std::round(k), 1e-9) << grid;
    // The largest such: one step fewer would break the bound.
    if (std::round(k) > 1) {
      EXPECT_GT(1.0 / (60 * (std::round(k) - 1)), water::max_time_step(p)) << grid;
    }
  }
  water::WaveParams fixed;
  fixed.time_step = 0.004;
  EXPECT_EQ(water::step_seconds(fixed), 0.004);
}

TEST(SceneWater, WaterIsASurfaceThatIsNotFitted) {
  json slab = pool();
  slab["object"]["shape"] = "slab";
  expect_rejected(slab, "object.shape");
  json fitted = pool();
  fitted["object"]["fit_size"] = 10;
  expect_rejected(fitted, "object.fit_size");
  json surface = pool();
  surface["object"]["shape"] = "surface";
  EXPECT_EQ(scene_from_json(surface, ".").object.shape, Shape::surface);
  surface["object"]["shape"] = nullptr;  // the default, which water makes a surface
  EXPECT_EQ(scene_from_json(surface, ".").object.shape, Shape::surface);
}

TEST(SceneWater, AMeshBesideWaterIsWarnedAbout) {
  json doc = pool();
  doc["mesh"] = "m.obj";
  const Scene s = scene_from_json(doc, ".");
  const auto warned = shape_overrides(doc, s);
  ASSERT_EQ(warned.size(), 1u);
  EXPECT_EQ(warned[0].first, "mesh");
  EXPECT_TRUE(shape_overrides(pool(), scene_from_json(pool(), ".")).empty());
}

TEST(SceneWater, APatchRetunesTheRainAndNullRestoresIt) {
  const Scene origin = scene_from_json(pool_with("rain_rate", 5), ".");
  const Scene wet = apply_merge_patch(origin, json{{"water", {{"rain_rate", 20}, {"paused", true}}}}, &origin);
  EXPECT_EQ(wet.water->rain_rate, 20);
  EXPECT_TRUE(wet.water->paused);
  EXPECT_EQ(wet.water->grid, origin.water->grid);
  const Scene back = apply_merge_patch(wet, json{{"water", {{"rain_rate", nullptr}}}}, &origin);
  EXPECT_EQ(back.water->rain_rate, 5);
  EXPECT_THROW(apply_merge_patch(origin, json{{"water", {{"time_step", 1.0}}}}, &origin), SceneError);
}

TEST(SceneWater, APatchOfTheOtherKindOfSceneNamesItsKeyAndTheScenesShape) {
  // The merged scene holds the shape it has: water patched into a slab was
  // refused as "object.shape: water is a surface", a key the patch never wrote.
  const Scene slab = scene_from_json(minimal(), ".");
  const auto said = [](const Scene& s, const json& patch) {
    return refusal<SceneError>([&] { apply_merge_patch(s, patch); });
  };
  EXPECT_EQ(said(slab, {{"water", {{"grid", 64}}}}),
            "water.grid: belongs to a water scene, and this scene has no water: its object is a slab (object.shape "
            "\"slab\"), read from its mesh file");
  EXPECT_EQ(refused_key<SceneError>([&] { apply_merge_patch(slab, {{"water", json::object()}}); }), "water");
  json solid = minimal();
  solid["object"]["shape"] = "solid";
  EXPECT_NE(said(scene_from_json(solid, "."), {{"water", {{"rain_rate", 3}}}}).find("water.rain_rate: belongs to a "
                                                                                  "water scene"),
            std::string::npos);
  // The reverse: a water scene given another shape, or its water taken away
  // (the refusal was "mesh: must not be empty").
  const Scene water = scene_from_json(pool(), ".");
  EXPECT_EQ(said(water, {{"object", {{"shape", "solid"}}}}),
            "object.shape: is \"solid\", but this is a water scene: its object is the water's surface (\"surface\", or "
            "leave object.shape out)");
  EXPECT_NE(said(water, {{"water", nullptr}}).find("water: is this scene's object"), std::string::npos);
  // What stays: a surface takes water (its mesh then unread), a patch that
  // writes the shape is answered by its shape, and a water scene given a
  // mesh in place of its water is a slab again.
  json surface = minimal();
  surface["object"]["shape"] = "surface";
  EXPECT_TRUE(apply_merge_patch(scene_from_json(surface, "."), {{"water", json::object()}}).water);
  EXPECT_EQ(refused_key<SceneError>([&] {
              apply_merge_patch(slab, {{"water", json::object()}, {"object", {{"shape", "solid"}}}});
            }),
            "object.shape");
  EXPECT_FALSE(apply_merge_patch(water, {{"water", nullptr}, {"mesh", "m.obj"}}).water);
}

// Patches given together (the CLI's --set, one patch each) are validated
// once, at the end: water's keys before the shape that takes them were
// refused as belonging to another kind of scene, the reverse order taken.
TEST(SceneWater, PatchesGivenTogetherAreJudgedTogetherInEitherOrder) {
  const Scene slab = scene_from_json(minimal(), ".");
  const json water = {{"water", {{"grid", 64}}}}, shape = {{"object", {{"shape", "surface"}}}};
  const Scene one = apply_merge_patches(slab, {water, shape}), other = apply_merge_patches(slab, {shape, water});
  ASSERT_TRUE(one.water && other.water);
  EXPECT_EQ(one.water->grid, 64);
  EXPECT_EQ(scene_to_json(one), scene_to_json(other));
  // Alone, each refusal is as before, naming the key written.
  EXPECT_EQ(refused_key<SceneError>([&] { apply_merge_patches(slab, {water}); }), "water.grid");
  EXPECT_EQ(refused_key<SceneError>([&] { apply_merge_patches(slab, {water, {{"post", {{"gamma", 2}}}}}); }),
            "water.grid");
}
