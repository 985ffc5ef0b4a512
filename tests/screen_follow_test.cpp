// SPDX-License-Identifier: LGPL-2.1-or-later
// screen.follow_light against geometry worked by hand: a 10 mm slab whose
// flat face lies at z = 0, its middle on the z axis, the screen plane 50 mm
// below. Turned by theta, parallel light lands d tan(theta) off the axis; a
// point light at height h above the face throws the middle's shadow
// d (x_l / h) the other way; a mirror sends light back up.
#include "caustic/scene.hpp"
#include "caustic/scene_warnings.hpp"
#include "caustic/screen_follow.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

using namespace caustic;
using nlohmann::json;

namespace {

Mesh slab() {
  Mesh m;
  m.positions = {{-5, -5, -1}, {5, -5, -1}, {5, 5, -1}, {-5, 5, -1}};
  m.normals.assign(4, {0, 0, -1});
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

Scene following() {
  json doc = {{"mesh", "m.obj"}, {"object", {{"flat_face_offset", 0}}}, {"light", {{"direction", {0, 0, -1}}}}};
  doc["screen"] = {{"center", {0, 0, -50}}, {"normal", {0, 0, 1}}, {"width", 40}, {"height", 40}, {"follow_light", true}};
  return scene_from_json(doc, ".");
}

constexpr double kDeg = std::numbers::pi / 180;

}  // namespace

TEST(ScreenFollow, ParallelLightMovesTheRectangleByDistanceTimesTangent) {
  const Mesh m = slab();
  Scene s = following();
  const Placement p = place_object(s.object, m);
  for (const double theta : {0.0, 20.0, 34.0, 60.0}) {
    s.light.direction = {std::sin(theta * kDeg), 0, -std::cos(theta * kDeg)};
    const Scene out = follow_light(s, p);
    EXPECT_NEAR(out.screen.center.x, 50 * std::tan(theta * kDeg), 1e-9) << theta;
    EXPECT_NEAR(out.screen.center.y, 0, 1e-9);
    EXPECT_NEAR(out.screen.center.z, -50, 1e-9) << "the plane stays";
    // What a visitor sees: the proxy's light stays on the rectangle.
    EXPECT_DOUBLE_EQ(proxy_share_on_screen(out, p), 1.0) << theta;
  }
  // The 34 degree drag of the report: without following, most of it is lost.
  s.light.direction = {std::sin(34 * kDeg), 0, -std::cos(34 * kDeg)};
  s.screen.follow_light = false;
  EXPECT_EQ(follow_light(s, p).screen.center, s.screen.center);
  EXPECT_LT(proxy_share_on_screen(s, p), 0.5);
}

TEST(ScreenFollow, PointLightThrowsTheShadowOfTheMiddle) {
  const Mesh m = slab();
  Scene s = following();
  s.light.type = LightType::point;
  s.light.position = {10, -4, 100};  // 100 mm above the middle of the flat face
  const Scene out = follow_light(s, place_object(s.object, m));
  // Similar triangles: 50 mm further down, the line has moved half the
  // light's offset the other way.
  EXPECT_NEAR(out.screen.center.x, -5, 1e-9);
  EXPECT_NEAR(out.screen.center.y, 2, 1e-9);
}

TEST(ScreenFollow, MirrorLightGoesUpAndGrazingLightIsBounded) {
  const Mesh m = slab();
  Scene s = following();
  const Placement p = place_object(s.object, m);
  // A mirror under light from straight above sends it up, away from a
  // screen below: nothing to follow, the rectangle stays.
  Scene mirror = s;
  mirror.object.material = Material::reflective;
  EXPECT_FALSE(light_footprint(mirror, p).has_value());
  EXPECT_EQ(follow_light(mirror, p).screen.center, s.screen.center);
  // With the screen above (facing down) it follows the reflection: light
  // falling at 30 degrees leaves at 30 degrees on the other side of the normal.
  mirror.screen.center = {0, 0, 80};
  mirror.screen.normal = {0, 0, -1};
  mirror.light.direction = {std::sin(30 * kDeg), 0, -std::cos(30 * kDeg)};
  EXPECT_NEAR(follow_light(mirror, p).screen.center.x, 80 * std::tan(30 * kDeg), 1e-9);
  // Grazing: at most kMaxFollow screen sizes from the foot of the object.
  s.light.direction = {std::sin(89.9 * kDeg), 0, -std::cos(89.9 * kDeg)};
  EXPECT_NEAR(follow_light(s, p).screen.center.x, kMaxFollow * 40, 1e-9);
  // Parallel to the plane: no footprint.
  s.light.direction = {1, 0, 0};
  EXPECT_FALSE(light_footprint(s, p).has_value());
}

TEST(ScreenFollow, ReadWrittenAndAWrittenCentreIsNamed) {
  const Scene s = following();
  EXPECT_TRUE(s.screen.follow_light);
  EXPECT_EQ(scene_to_json(s)["screen"]["follow_light"], true);
  EXPECT_FALSE(scene_from_json({{"mesh", "m.obj"}}, ".").screen.follow_light) << "off unless a scene asks";
  const auto named = follow_overrides({{"screen", {{"center", {1, 2, -50}}}}}, s);
  ASSERT_EQ(named.size(), 1u);
  EXPECT_EQ(named[0].first, "screen.center");
  EXPECT_TRUE(follow_overrides({{"screen", {{"center", {0, 0, -50}}}}}, s).empty()) << "used as written";
  EXPECT_TRUE(follow_overrides({{"screen", {{"width", 30}}}}, s).empty());
  EXPECT_TRUE(follow_overrides({{"screen", {{"center", nullptr}}}}, s).empty());
  Scene fixed = s;
  fixed.screen.follow_light = false;
  fixed.screen.center = {1, 2, -50};
  EXPECT_TRUE(follow_overrides({{"screen", {{"center", {1, 2, -50}}}}}, fixed).empty());
}

TEST(ScreenFollow, CachedBoundsPlaceLikeTheVertices) {
  const Mesh m = slab();
  Scene s = following();
  s.object.position = {3, -7, 11};
  s.object.rotation_deg = {10, -25, 40};
  s.object.fit_size = 30;
  const Placement a = place_object(s.object, m), b = place_object(s.object, mesh_bounds(m, s.object.flat_face_normal));
  EXPECT_EQ(a.center, b.center);
  EXPECT_EQ(a.box, b.box);
  EXPECT_EQ(a.model, b.model);
  EXPECT_THROW(place_object(s.object, mesh_bounds(m, {1, 0, 0})), std::invalid_argument);
}

// A mirror focused with focus_distance: the screen faces back along the
// reflection, at that distance from the object, and the light lands on it.
TEST(ScreenFollow, AMirrorsFocusDistancePlacesTheScreenOnTheReflection) {
  json doc = {{"mesh", "m.obj"},
              {"focus_distance", 60},
              {"object", {{"material", "reflective"}, {"flat_face_offset", 0}}},
              {"light", {{"direction", {0, 0, -1}}}}};
  Scene s = scene_from_json(doc, ".");
  EXPECT_NEAR(glm::length(s.screen.normal - glm::dvec3(0, 0, -1)), 0, 1e-12);
  EXPECT_NEAR(glm::length(s.screen.center - glm::dvec3(0, 0, 60)), 0, 1e-12);
  const Mesh m = slab();
  EXPECT_TRUE(light_warnings(s, place_object(s.object, m)).empty());
  // Light falling at 30 degrees leaves at 30 degrees on the other side.
  doc["light"]["direction"] = {std::sin(30 * kDeg), 0, -std::cos(30 * kDeg)};
  s = scene_from_json(doc, ".");
  EXPECT_NEAR(s.screen.center.x, 60 * std::sin(30 * kDeg), 1e-9);
  EXPECT_NEAR(s.screen.center.z, 60 * std::cos(30 * kDeg), 1e-9);
  EXPECT_TRUE(light_warnings(s, place_object(s.object, m)).empty());
  // A normal or centre written is the writer's; a refractive object keeps the default.
  doc["screen"] = {{"normal", {0, 0, 1}}};
  EXPECT_EQ(scene_from_json(doc, ".").screen.normal, glm::dvec3(0, 0, 1));
  doc.erase("screen");
  doc["object"]["material"] = "refractive";
  EXPECT_EQ(scene_from_json(doc, ".").screen.normal, glm::dvec3(0, 0, 1));
}
