// SPDX-License-Identifier: LGPL-2.1-or-later
// Scene JSON: defaults, round trip, merge patches, --set assignments and
// every kind of bad input, each rejected with the offending key named.
#include "caustic/json_text.hpp"
#include "caustic/param_store.hpp"
#include "caustic/scene.hpp"
#include "caustic/scene_warnings.hpp"
#include "scene_test_support.hpp"
#include "refusal.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace caustic;
using nlohmann::json;

using caustic::testing::expect_rejected;
using caustic::testing::minimal;
using caustic::testing::with;

TEST(SceneJson, DefaultsAreFilledIn) {
  const Scene s = scene_from_json(minimal(), "/data");
  EXPECT_EQ(s.mesh_path(), std::filesystem::path("/data/m.obj"));
  EXPECT_EQ(s.object.material, Material::refractive);
  EXPECT_DOUBLE_EQ(s.object.ior, 1.5);
  EXPECT_EQ(s.render.intensity, IntensityMode::energy);
  EXPECT_FALSE(s.object.fit_size);
}

TEST(SceneJson, RoundTripsThroughJson) {
  json doc = minimal();
  doc["object"] = {{"material", "reflective"}, {"ior", 1.7}, {"flat_face_normal", {0, 2, 0}}, {"fit_size", 100},
                   {"flat_face_offset", -3.5}, {"rotation_deg", {10, 20, 30}}};
  doc["light"] = {{"type", "point"}, {"position", {1, 2, 3}}, {"point_model", "approximate"}};
  doc["render"] = {{"intensity", "report"}, {"fresnel", false}, {"width", 640}, {"height", 480}};
  const Scene s = scene_from_json(doc, ".");
  EXPECT_DOUBLE_EQ(s.object.flat_face_normal.y, 1.0);  // normalised
  EXPECT_EQ(scene_from_json(scene_to_json(s), "."), s);
}

TEST(SceneJson, FocusDistancePlacesTheScreen) {
  json doc = minimal();
  doc["focus_distance"] = 80;
  doc["object"]["position"] = {1, 2, 3};
  doc["screen"] = {{"normal", {0, 0, 1}}};
  const Scene s = scene_from_json(doc, ".");
  EXPECT_EQ(s.screen.center, glm::dvec3(1, 2, -77));
  // An explicit centre wins.
  doc["screen"]["center"] = {0, 0, -5};
  EXPECT_EQ(scene_from_json(doc, ".").screen.center, glm::dvec3(0, 0, -5));
  // A far object and a long focus may not put the screen beyond the limit
  // that a written centre has (the parser once let it through).
  doc["screen"].erase("center");
  doc["object"]["position"] = {0, 0, -1e6};
  doc["focus_distance"] = 1e6;
  try {
    scene_from_json(doc, ".");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "focus_distance");
  }
}

TEST(SceneJson, UpIsMadePerpendicularToTheNormal) {
  json doc = minimal();
  doc["screen"] = {{"normal", {0, 0, 1}}, {"up", {0, 1, 1}}};
  const Scene s = scene_from_json(doc, ".");
  EXPECT_NEAR(glm::dot(s.screen.up, s.screen.normal), 0.0, 1e-15);
  EXPECT_NEAR(s.screen.up.y, 1.0, 1e-15);
}

TEST(SceneJson, RejectsBadValuesNamingTheKey) {
  expect_rejected(json{{"object", {{"ior", 1.5}}}}, "mesh");
  expect_rejected(json{{"mesh", 3}}, "mesh");
  expect_rejected(json{{"mesh", ""}}, "mesh");
  expect_rejected(json::array(), "");
  expect_rejected(with("object", "ior", "glass"), "object.ior");
  expect_rejected(with("object", "ior", 0.5), "object.ior");
  expect_rejected(with("object", "ior", 1e9), "object.ior");
  expect_rejected(with("object", "material", "wood"), "object.material");
  expect_rejected(with("object", "flat_face_normal", {0, 0, 0}), "object.flat_face_normal");
  expect_rejected(with("object", "flat_face_normal", {0, 1}), "object.flat_face_normal");
  expect_rejected(with("object", "position", {0, "a", 1}), "object.position");
  expect_rejected(with("object", "position", {0, 1e7, 1}), "object.position");
  expect_rejected(with("object", "fit_size", 0), "object.fit_size");
  expect_rejected(with("object", "fit_size", -2), "object.fit_size");
  expect_rejected(with("light", "type", "spot"), "light.type");
  expect_rejected(with("light", "direction", {0, 0, 0}), "light.direction");
  expect_rejected(with("light", "point_model", "fast"), "light.point_model");
  expect_rejected(with("screen", "width", 0), "screen.width");
  expect_rejected(with("screen", "height", -1), "screen.height");
  expect_rejected(with("screen", "up", {0, 0, 1}), "screen.up");  // parallel to the default normal
  expect_rejected(with("render", "width", 8), "render.width");
  expect_rejected(with("render", "height", 1.5), "render.height");
  expect_rejected(with("render", "intensity", "area"), "render.intensity");
  expect_rejected(with("render", "fresnel", 1), "render.fresnel");
  expect_rejected(with("post", "exposure", 0), "post.exposure");
  expect_rejected(with("post", "gamma", 0.0), "post.gamma");
  expect_rejected(with("post", "bloom_radius", 100), "post.bloom_radius");
  expect_rejected(with("post", "bloom_strength", -1), "post.bloom_strength");
  expect_rejected(json{{"mesh", "m.obj"}, {"focus_distance", -1}}, "focus_distance");
  // Shown in the gallery: no NUL, no escape sequence (as the designer's --name).
  expect_rejected(json{{"mesh", "m.obj"}, {"name", std::string("a\0b", 3)}}, "name");
  expect_rejected(json{{"mesh", "m.obj"}, {"description", "\x1b[2Jcleared"}}, "description");
  // Unicode's controls too: NEL (a C1 control), a line separator, and a
  // right-to-left override that shows what follows it reversed.
  for (const char* shown : {"a\u0085b", "two\u2028lines", "photo\u202egpj.exe", "x\u2066y"})
    expect_rejected(json{{"mesh", "m.obj"}, {"name", shown}}, "name");
  EXPECT_NO_THROW(scene_from_json(json{{"mesh", "m.obj"}, {"name", "Caf\u00e9 \u2014 \u732b"}}, "."));
  // The limits count bytes of UTF-8, as the designer's --name does, and say
  // so: 101 "é" are 202 bytes (the answer said 200 "characters").
  std::string accents;
  for (int i = 0; i < 101; ++i) accents += "\u00e9";
  try {
    scene_from_json(json{{"mesh", "m.obj"}, {"name", accents}}, ".");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("name: is longer than 200 bytes"), std::string::npos) << e.what();
  }
}

TEST(SceneJson, RejectsUnknownKeysAtEveryLevel) {
  expect_rejected(json{{"mesh", "m.obj"}, {"colour", "red"}}, "colour");
  expect_rejected(with("object", "iorr", 1.5), "object.iorr");
  expect_rejected(with("light", "power", 2), "light.power");
  expect_rejected(with("screen", "depth", 2), "screen.depth");
  expect_rejected(with("render", "fidelity", "max"), "render.fidelity");
  expect_rejected(with("post", "vignette", 1), "post.vignette");
  expect_rejected(json{{"mesh", "m.obj"}, {"object", 5}}, "object");
}

// A key is the client's text: quoted in the message, a NUL would end it
// (what() would read as empty) and control bytes would reach the log raw.
TEST(SceneJson, QuotesUnknownKeysSafely) {
  expect_rejected(json{{"mesh", "m.obj"}, {std::string("\0x", 2), 1}}, "\\x00x");
  expect_rejected(with("light", "a\nb", 1), "light.a\\x0ab");
  expect_rejected(json{{"mesh", "m.obj"}, {"", 1}}, "\"\"");
  expect_rejected(json{{"mesh", "m.obj"}, {std::string(500, 'k'), 1}}, std::string(64, 'k') + "...");
}

TEST(SceneJson, RejectsNanAndInfinity) {
  // JSON has no NaN literal; a client that sends one through a library that
  // writes it as a number still has to be stopped before the GPU.
  expect_rejected(with("object", "ior", std::nan("")), "object.ior");
  expect_rejected(with("post", "exposure", INFINITY), "post.exposure");
  expect_rejected(with("light", "position", {0, NAN, 1}), "light.position");
}

TEST(MergePatch, ChangesOnlyWhatItNames) {
  const Scene s = scene_from_json(minimal(), ".");
  const Scene p = apply_merge_patch(s, json{{"object", {{"ior", 1.8}}}, {"post", {{"gamma", 1.0}}}});
  EXPECT_DOUBLE_EQ(p.object.ior, 1.8);
  EXPECT_DOUBLE_EQ(p.post.gamma, 1.0);
  EXPECT_EQ(p.light, s.light);
  EXPECT_EQ(p.screen, s.screen);
}

TEST(MergePatch, NullRestoresTheDefault) {
  Scene s = scene_from_json(with("object", "fit_size", 50), ".");
  ASSERT_TRUE(s.object.fit_size);
  EXPECT_FALSE(apply_merge_patch(s, json{{"object", {{"fit_size", nullptr}}}}).object.fit_size);
}

// A session resets to its own scene: a null takes the origin's value, at any
// level, and falls back to the default only where the origin has none.
TEST(MergePatch, NullRestoresTheOriginsValueWhenGiven) {
  json doc = minimal();
  doc["object"]["ior"] = 1.7;
  doc["post"]["gamma"] = 1.8;
  doc["post"]["exposure"] = 0.5;
  const Scene origin = scene_from_json(doc, ".");
  const Scene changed = apply_merge_patch(
      origin, json{{"object", {{"ior", 1.3}, {"fit_size", 10}}}, {"post", {{"gamma", 1.0}, {"exposure", 2.0}}}});
  const Scene one = apply_merge_patch(changed, json{{"object", {{"ior", nullptr}, {"fit_size", nullptr}}}}, &origin);
  EXPECT_DOUBLE_EQ(one.object.ior, 1.7);
  EXPECT_FALSE(one.object.fit_size);  // the origin has none: the default
  EXPECT_DOUBLE_EQ(one.post.gamma, 1.0);
  const Scene section = apply_merge_patch(changed, json{{"post", nullptr}}, &origin);
  EXPECT_DOUBLE_EQ(section.post.gamma, 1.8);
  EXPECT_DOUBLE_EQ(section.post.exposure, 0.5);
  EXPECT_DOUBLE_EQ(section.object.ior, 1.3);
  // Without an origin a null is RFC 7396's: the default.
  EXPECT_DOUBLE_EQ(apply_merge_patch(changed, json{{"object", {{"ior", nullptr}}}}).object.ior, Scene{}.object.ior);
}

TEST(ParamStore, ANullInAPatchRestoresTheInitialScenesValue) {
  json doc = minimal();
  doc["light"]["direction"] = {0.0, 0.6, -0.8};
  ParamStore store(scene_from_json(doc, "."));
  store.apply_patch(json{{"light", {{"direction", {0, 0, -1}}}}});
  store.apply_patch(json{{"light", {{"direction", nullptr}}}});
  EXPECT_NEAR(store.snapshot().scene.light.direction.y, 0.6, 1e-12);
}

TEST(MergePatch, RejectedPatchLeavesTheSceneAlone) {
  const Scene s = scene_from_json(minimal(), ".");
  const Scene before = s;
  EXPECT_THROW(apply_merge_patch(s, json{{"object", {{"ior", -1}}}}), SceneError);
  EXPECT_THROW(apply_merge_patch(s, json{{"nonsense", 1}}), SceneError);
  EXPECT_THROW(apply_merge_patch(s, json::array({1, 2})), SceneError);
  EXPECT_EQ(s, before);
}

TEST(MergePatch, FocusDistanceMovesTheScreen) {
  json doc = minimal();
  doc["focus_distance"] = 80;
  const Scene s = scene_from_json(doc, ".");
  EXPECT_DOUBLE_EQ(apply_merge_patch(s, json{{"focus_distance", 40}}).screen.center.z, -40.0);
}

TEST(Assignment, BuildsNestedPatches) {
  EXPECT_EQ(patch_from_assignment("object.ior=1.7"), (json{{"object", {{"ior", 1.7}}}}));
  EXPECT_EQ(patch_from_assignment("light.direction=[0,0.5,-1]"),
            (json{{"light", {{"direction", {0, 0.5, -1}}}}}));
  EXPECT_EQ(patch_from_assignment("object.material=reflective"),
            (json{{"object", {{"material", "reflective"}}}}));
  EXPECT_EQ(patch_from_assignment("name=My scene"), (json{{"name", "My scene"}}));
}

TEST(Assignment, RejectsMalformedText) {
  EXPECT_THROW(patch_from_assignment("object.ior"), SceneError);
  EXPECT_THROW(patch_from_assignment("=3"), SceneError);
  EXPECT_THROW(patch_from_assignment("object..ior=3"), SceneError);
  EXPECT_THROW(patch_from_assignment(".ior=3"), SceneError);
}

TEST(LoadScene, ReportsMissingFilesAndBadJson) {
  const auto dir = std::filesystem::temp_directory_path() / "caustic_scene_test";
  std::filesystem::create_directories(dir);
  EXPECT_EQ(caustic::testing::refusal<SceneError>([&] { load_scene(dir / "absent.json"); }),
            "cannot open scene file " + (dir / "absent.json").string() + " (No such file or directory)");
  std::ofstream(dir / "broken.json") << "{\"mesh\": \"a.obj\",";
  try {
    load_scene(dir / "broken.json");
    ADD_FAILURE() << "accepted broken JSON";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("not valid JSON"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "good.json") << R"({"mesh": "a.obj", "object": {"ior": 1.6}})";
  nlohmann::json written;
  const Scene s = load_scene(dir / "good.json", &written);
  EXPECT_EQ(s.mesh_path(), dir / "a.obj");
  EXPECT_DOUBLE_EQ(s.object.ior, 1.6);
  EXPECT_EQ(written, nlohmann::json::parse(R"({"mesh": "a.obj", "object": {"ior": 1.6}})"));
}

// A scene file is parsed as every outside JSON text is (json_text.hpp):
// nothing after a NUL is ignored, nesting is bounded, and a file that
// never ends is not read whole.
TEST(LoadScene, RefusesWhatTheJsonRulesRefuse) {
  const auto dir = std::filesystem::temp_directory_path() / "caustic_scene_test";
  std::filesystem::create_directories(dir);
  const auto refused = [](const std::filesystem::path& file) {
    return caustic::testing::refusal<SceneError>([&] { load_scene(file); });
  };
  {
    std::ofstream out(dir / "nul.json", std::ios::binary);
    out << R"({"mesh": "a.obj"})" << '\0' << "junk";
  }
  EXPECT_NE(refused(dir / "nul.json").find("not valid JSON"), std::string::npos) << refused(dir / "nul.json");
  EXPECT_NE(refused(dir / "nul.json").find("at line 1, column 18 (byte 17)"), std::string::npos) << refused(dir / "nul.json");
  // Where a hand-edited file broke, as an editor counts: the "}" where the
  // value should be is line 3, column 21.
  std::ofstream(dir / "lines.json") << "{\n  \"mesh\": \"a.obj\",\n  \"object\": {\"ior\": }\n}\n";
  EXPECT_NE(refused(dir / "lines.json").find("at line 3, column 21 (byte 41)"), std::string::npos)
      << refused(dir / "lines.json");
  std::ofstream(dir / "huge.json") << "{\"mesh\": \"a.obj\",\n\"focus_distance\": -1e309}";
  EXPECT_NE(refused(dir / "huge.json").find("a number beyond the range of a double"), std::string::npos)
      << refused(dir / "huge.json");
  std::ofstream(dir / "deep.json") << R"({"mesh": "a.obj", "x": )" << std::string(100000, '[')
                                   << std::string(100000, ']') << "}";
  EXPECT_NE(refused(dir / "deep.json").find("nested deeper than"), std::string::npos) << refused(dir / "deep.json");
  // A few bytes a value, ~130 built: a 16 MiB file of them held 750 MB.
  // The object, "a.obj" and the array are 3 values; each {} one more.
  const std::string many = R"({"mesh": "a.obj", "x": [)";
  const auto values = [&](std::size_t n) {
    std::string text = many;
    for (std::size_t i = 4; i < n; ++i) text += "{},";
    return text + "{}]}";
  };
  std::ofstream(dir / "many.json") << values(kMaxJsonValues + 1);
  const std::string at = "(byte " + std::to_string(many.size() + 3 * (kMaxJsonValues - 3)) + ")";
  EXPECT_NE(refused(dir / "many.json").find("more than 100000 values in one JSON text at line 1"), std::string::npos)
      << refused(dir / "many.json").substr(0, 300);
  EXPECT_NE(refused(dir / "many.json").find(at), std::string::npos) << refused(dir / "many.json").substr(0, 300) << at;
  std::ofstream(dir / "enough.json") << values(kMaxJsonValues);  // refused for its key, not its count
  EXPECT_EQ(refused(dir / "enough.json").find("values in one JSON text"), std::string::npos)
      << refused(dir / "enough.json").substr(0, 300);
  {
    std::ofstream out(dir / "big.json", std::ios::binary);
    out << R"({"mesh": "a.obj", "description": ")" << std::string(kMaxSceneFileBytes, 'a') << "\"}";
  }
  EXPECT_NE(refused(dir / "big.json").find("larger than 16 MiB"), std::string::npos);
  // Devices are not opened: /dev/zero was read to the limit, a terminal waited for its user.
  EXPECT_NE(refused("/dev/zero").find("device or kernel file, not a file"), std::string::npos) << refused("/dev/zero");
  EXPECT_NE(refused(dir).find("is a folder, pipe, socket, device"), std::string::npos) << refused(dir);
  std::ofstream(dir / "nulmesh.json") << R"({"mesh": "a.obj\u0000junk"})";
  EXPECT_NE(refused(dir / "nulmesh.json").find("mesh: must not hold control characters"), std::string::npos)
      << refused(dir / "nulmesh.json");
  std::filesystem::remove(dir / "big.json");
}

// Warnings are judged on the proxy (the bounding slab): light straight down
// through a 10 mm slab onto a 40 mm screen below lands; turned away, sent
// beside the screen or mirrored away, it does not, and the warning names
// the setting to change.
TEST(LightWarnings, NameWhatSendsTheLightAwayFromTheScreen) {
  Mesh slab;
  slab.positions = {{-5, -5, -1}, {5, -5, -1}, {5, 5, -1}, {-5, 5, -1}};
  slab.normals.assign(4, {0, 0, -1});
  slab.triangles = {{0, 1, 2}, {0, 2, 3}};
  json doc = minimal();
  doc["object"]["flat_face_offset"] = 0;
  doc["screen"] = {{"center", {0, 0, -50}}, {"normal", {0, 0, 1}}, {"width", 40}, {"height", 40}};
  doc["light"]["direction"] = {0, 0, -1};
  Scene s = scene_from_json(doc, ".");
  const Placement p = place_object(s.object, slab);
  EXPECT_TRUE(light_warnings(s, p).empty());
  EXPECT_DOUBLE_EQ(proxy_share_on_screen(s, p), 1.0);

  Scene up = s;
  up.light.direction = {0, 0, 1};  // from below the screen, away from it... and through the back face
  ASSERT_EQ(light_warnings(up, p).size(), 1u);
  EXPECT_EQ(light_warnings(up, p)[0].key, "light.direction");
  // A point light below the object shines away from the screen too, but it
  // is aimed by where it stands: light.direction, which it ignores, was named.
  Scene below = s;
  below.light.type = LightType::point;
  below.light.position = {0, 0, -30};
  ASSERT_EQ(light_warnings(below, p).size(), 1u);
  EXPECT_EQ(light_warnings(below, p)[0].key, "light.position");

  Scene beside = s;
  beside.light.direction = glm::normalize(glm::dvec3(0.8, 0, -0.6));  // lands 67 mm off the centre
  ASSERT_EQ(light_warnings(beside, p).size(), 1u);
  EXPECT_EQ(light_warnings(beside, p)[0].key, "screen.center");

  Scene mirror = s;
  mirror.object.material = Material::reflective;
  ASSERT_EQ(light_warnings(mirror, p).size(), 1u);
  EXPECT_EQ(light_warnings(mirror, p)[0].key, "object.material");

  Scene half = s;  // tilted to shift the light 22 mm: the outline spans 17..27 mm, 3 mm of it land
  half.light.direction = glm::normalize(glm::dvec3(0.44, 0, -1));
  EXPECT_GT(proxy_share_on_screen(half, p), 0.0);
  EXPECT_LT(proxy_share_on_screen(half, p), 0.5);
}

// A prism bends its light towards its base, away from where a slab's would
// land: a 35-degree wedge of index 1.5 under light along -z deviates it by
// asin(1.5 sin 35°) - 35° = 24.4° towards +x, about 20 mm over the 45 mm to
// a screen there. The box a wedge fills is thick across its width, so the
// proxy may be such a wedge, and the screen where the prism's light lands
// is not said to be beside it; one where no wedge the box holds could send
// it still is.
TEST(LightWarnings, AWedgesLightIsNotSaidToMissTheScreenItLandsOn) {
  Mesh wedge;
  const double drop = 10 * std::tan(glm::radians(35.0));
  wedge.positions = {{-5, -5, -1}, {5, -5, -1 - drop}, {5, 5, -1 - drop}, {-5, 5, -1}};
  wedge.normals.assign(4, glm::normalize(glm::dvec3(-std::sin(glm::radians(35.0)), 0, -std::cos(glm::radians(35.0)))));
  wedge.triangles = {{0, 1, 2}, {0, 2, 3}};
  json doc = minimal();
  doc["object"]["flat_face_offset"] = 0;
  doc["object"]["ior"] = 1.5;
  doc["screen"] = {{"center", {20, 0, -50}}, {"normal", {0, 0, 1}}, {"width", 20}, {"height", 20}};
  doc["light"]["direction"] = {0, 0, -1};
  const Scene s = scene_from_json(doc, ".");
  const Placement p = place_object(s.object, wedge);
  EXPECT_EQ(proxy_share_on_screen(s, p), 0.0) << "the flat slab's light passes beside";
  EXPECT_TRUE(light_warnings(s, p).empty()) << light_warnings(s, p)[0].detail;
  Scene far = s;  // 60 mm off: beyond what a wedge of the box's slope (at most 38.7°) deviates
  far.screen.center = {80, 0, -50};
  ASSERT_EQ(light_warnings(far, p).size(), 1u);
  EXPECT_EQ(light_warnings(far, p)[0].key, "screen.center");
}
