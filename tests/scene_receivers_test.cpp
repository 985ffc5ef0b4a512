// SPDX-License-Identifier: LGPL-2.1-or-later
// The receivers key: rectangles parsed and written back, bad ones named by
// their index, the atlas's tiles, and the first surface a ray meets.
#include "caustic/receivers.hpp"
#include "caustic/surfaces.hpp"
#include "refusal.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

using namespace caustic;
using namespace caustic::testing;

namespace {

json floor_rectangle() {
  return {{"center", {0, 0, -30}}, {"normal", {0, 0, 1}}, {"up", {0, 1, 0}}, {"width", 50}, {"height", 40}};
}

}  // namespace

TEST(SceneReceivers, RectanglesRoundTrip) {
  json doc = minimal();
  doc["receivers"] = {floor_rectangle(), {{"center", {25, 0, -20}}, {"normal", {-2, 0, 0}}, {"up", {0, 0, 3}}}};
  const Scene s = scene_from_json(doc, ".");
  ASSERT_EQ(s.receivers.size(), 2u);
  EXPECT_EQ(s.receivers[0].width, 50);
  EXPECT_EQ(s.receivers[1].normal, glm::dvec3(-1, 0, 0));  // normalised
  EXPECT_EQ(s.receivers[1].up, glm::dvec3(0, 0, 1));
  EXPECT_EQ(scene_from_json(scene_to_json(s), "."), s);
  // null is the default: a rectangle, not an unknown key (nor, on the screen, a lathe refused).
  json rectangle = floor_rectangle();
  rectangle["lathe"] = nullptr;
  rectangle["mesh"] = nullptr;
  doc["receivers"] = {rectangle};
  doc["screen"] = {{"lathe", nullptr}, {"mesh", nullptr}};
  EXPECT_EQ(scene_from_json(doc, ".").receivers[0].width, 50);
  EXPECT_TRUE(scene_from_json(minimal(), ".").receivers.empty());
  EXPECT_TRUE(scene_to_json(scene_from_json(minimal(), "."))["receivers"].empty());
}

TEST(SceneReceivers, BadReceiversAreNamedByTheirPlace) {
  json doc = minimal();
  doc["receivers"] = json::array();
  for (int i = 0; i < 8; ++i) doc["receivers"].push_back(floor_rectangle());
  expect_rejected(doc, "receivers");
  doc["receivers"] = "floor";
  expect_rejected(doc, "receivers");
  json bad = floor_rectangle();
  bad["width"] = -1;
  doc["receivers"] = {floor_rectangle(), bad};
  expect_rejected(doc, "receivers[1].width");
  bad = floor_rectangle();
  bad["colour"] = "white";
  doc["receivers"] = {bad};
  expect_rejected(doc, "receivers[0].colour");
  bad = floor_rectangle();
  bad["up"] = {0, 0, 1};  // along its normal
  doc["receivers"] = {bad};
  expect_rejected(doc, "receivers[0].up");
  // Its own normal, not the screen's (which it named).
  EXPECT_EQ(refusal<SceneError>([&] { scene_from_json(doc, "."); }),
            "receivers[0].up: must not be parallel to receivers[0].normal");
  bad = floor_rectangle();
  bad["follow_light"] = true;
  doc["receivers"] = {bad};
  expect_rejected(doc, "receivers[0].follow_light");
  doc["receivers"] = {floor_rectangle()};
  doc["render"]["intensity"] = "report";
  expect_rejected(doc, "render.intensity");
}

TEST(SceneReceivers, APlaneThroughTheObjectIsRefused) {
  json doc = minimal();
  json through = floor_rectangle();
  through["center"] = {0, 0, -0.5};  // inside the slab (z from -1 to 1.5)
  doc["receivers"] = {floor_rectangle(), through};
  doc["object"]["flat_face_offset"] = 1.5;
  const Scene s = scene_from_json(doc, ".");
  const Mesh face = grid_mesh(sine_window(0.5, 1.0, 0.5, 1.0, 5), 9, 9);
  expect_geometry_refused(s, face, "receivers[1].center");
  EXPECT_THROW(check_geometry_public(s, place_object(s.object, face)), SceneError);
}

TEST(SceneReceivers, TheAtlasTilesTheSurfacesRowByRow) {
  EXPECT_EQ(atlas_layout(1024, 768, 1), (std::vector<AtlasTile>{{0, 0, 1024, 768}}));
  EXPECT_EQ(atlas_layout(1024, 768, 2), (std::vector<AtlasTile>{{0, 0, 512, 768}, {512, 0, 512, 768}}));
  const auto three = atlas_layout(1024, 1024, 3);  // 2 x 2, the last tile empty
  EXPECT_EQ(three[2], (AtlasTile{0, 512, 512, 512}));
  const auto eight = atlas_layout(1000, 1000, 8);  // 3 x 3 of 333 px
  EXPECT_EQ(eight[7], (AtlasTile{333, 666, 333, 333}));
}

TEST(SceneReceivers, ARayLandsOnTheFirstRectangleItMeets) {
  json doc = minimal();
  doc["screen"] = {{"center", {0, 0, -100}}};
  doc["receivers"] = {floor_rectangle()};
  const Scene s = scene_from_json(doc, ".");
  // Straight down from the origin: the floor (30 mm) before the screen (100 mm).
  ReceiverHit hit = first_receiver(s, {0, 0, 0}, {0, 0, -1});
  EXPECT_EQ(hit.index, 1);
  EXPECT_DOUBLE_EQ(hit.distance, 30);
  // Beside the floor's 50 mm: on to the screen, bounded now too (40 mm).
  hit = first_receiver(s, {30, 0, 0}, {0, 0, -1});
  EXPECT_EQ(hit.index, -1);
  hit = first_receiver(s, {0, 19, 0}, {0, 0, -1});
  EXPECT_EQ(hit.index, 1);
  EXPECT_DOUBLE_EQ(hit.local.y, 19);
  // Alone, the screen is its whole plane.
  Scene alone = s;
  alone.receivers.clear();
  EXPECT_EQ(first_receiver(alone, {300, 0, 0}, {0, 0, -1}).index, 0);
  EXPECT_EQ(first_receiver(alone, {0, 0, 0}, {0, 0, 1}).index, -1);  // behind the ray
}
