// SPDX-License-Identifier: LGPL-2.1-or-later
// A broadcast's room messages (src/server/room_messages.hpp): the largest
// scene the format allows (seven lathes of 64 profile points, every number
// with a long decimal tail) still goes in datagrams Janus passes whole, each
// receiver's tile is the one the one-viewer API reports, and what a viewer
// reads back places every surface within the rounding.
#include "room_messages.hpp"

#include "caustic/receivers.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace caustic::server {
namespace {

using nlohmann::json;
using caustic::testing::minimal;

json tile(const AtlasTile& t) { return {{"x", t.x}, {"y", t.y}, {"width", t.width}, {"height", t.height}}; }

// Seven lathes (the most receivers), each of the most profile points, their
// numbers with every decimal a double has.
json crowded_scene() {
  json doc = minimal();
  doc["render"] = {{"width", 1920}, {"height", 1080}};
  doc["light"] = {{"type", "point"}, {"position", {1.0 / 3, -200.0 / 7, 300.0 / 11}}};
  doc["receivers"] = json::array();
  for (std::size_t r = 0; r < kMaxReceivers; ++r) {
    json profile = json::array();
    for (std::size_t k = 0; k < kMaxLatheProfile; ++k)
      profile.push_back({10.0 + 1.0 / 3 + 0.0123456789 * k + r, 100.0 / 7 * k / kMaxLatheProfile});
    const double n = std::sqrt(14.0);
    doc["receivers"].push_back({{"center", {17.123456789 + r, -0.987654321 * r, -30.0 / 7}},
                                {"normal", {1 / n, 2 / n, 3 / n}},
                                {"up", {0.0, -3 / std::sqrt(13.0), 2 / std::sqrt(13.0)}},
                                {"lathe", {{"profile", profile}, {"segments", kMaxLatheSegments}}}});
  }
  return doc;
}

TEST(RoomMessages, TheLargestSceneFitsDatagramsAndEachSurfaceComesBackInPlace) {
  const Scene scene = scene_from_json(crowded_scene(), ".");
  ASSERT_EQ(scene.receivers.size(), kMaxReceivers);
  const auto messages = room_messages(scene, 42);
  ASSERT_EQ(messages.size(), 1 + kMaxReceivers);
  std::size_t largest = 0;
  for (const auto& m : messages) largest = std::max(largest, m.size());
  EXPECT_LE(largest, kRoomDatagramBytes);
  std::printf("largest room message: %zu bytes of %zu\n", largest, kRoomDatagramBytes);

  const auto tiles = atlas_layout(1920, 1080, 1 + kMaxReceivers);
  const json room = json::parse(messages[0]);
  EXPECT_EQ(room.at("version"), 42);
  EXPECT_EQ(room.at("params").at("receiver_count"), kMaxReceivers);
  EXPECT_EQ(room.at("params").at("render"), (json{{"width", 1920}, {"height", 1080}}));
  EXPECT_EQ(room.at("params").at("tile"), tile(tiles[0]));
  EXPECT_FALSE(room.at("params").contains("mesh"));
  EXPECT_EQ(room.at("params").at("light").at("position")[1].get<double>(), -200.0 / 7);  // the room exact

  // The surfaces as a viewer reads them, parsed again as a scene's receivers.
  json back = minimal();
  back["receivers"] = json::array();
  for (std::size_t i = 0; i < kMaxReceivers; ++i) {
    const json m = json::parse(messages[1 + i]);
    EXPECT_EQ(m.at("version"), 42);
    const json& r = m.at("receiver");
    EXPECT_EQ(r.at("index"), i);
    EXPECT_EQ(r.at("count"), kMaxReceivers);
    EXPECT_EQ(r.at("tile"), tile(tiles[1 + i]));
    back["receivers"].push_back(r.at("surface"));
  }
  const Scene read = scene_from_json(back, ".");
  for (std::size_t i = 0; i < kMaxReceivers; ++i) {
    const ScreenParams &a = scene.receivers[i], &b = read.receivers[i];
    EXPECT_LT(glm::length(a.center - b.center), 1e-4) << "receiver " << i;
    EXPECT_LT(glm::length(a.normal - b.normal), 2e-4) << "receiver " << i;
    ASSERT_TRUE(b.lathe);
    ASSERT_EQ(b.lathe->profile.size(), a.lathe->profile.size());
    for (std::size_t k = 0; k < a.lathe->profile.size(); ++k)
      ASSERT_LT(glm::length(a.lathe->profile[k] - b.lathe->profile[k]), 1e-4) << "receiver " << i << " point " << k;
  }
}

TEST(RoomMessages, ALatheAtTheLargestCoordinatesFitsRoundedToWholeUnitsAtWorst) {
  json doc = minimal();
  json profile = json::array();
  for (std::size_t k = 0; k < kMaxLatheProfile; ++k)
    profile.push_back({999999.123456 - k, -999999.654321 + k});
  doc["receivers"] = {{{"center", {-999999.5, -999999.25, -999999.125}},
                       {"normal", {0, 0, 1}},
                       {"up", {0, 1, 0}},
                       {"lathe", {{"profile", profile}, {"segments", kMaxLatheSegments}}}}};
  const Scene scene = scene_from_json(doc, ".");
  const auto messages = room_messages(scene, 3);
  ASSERT_EQ(messages.size(), 2u);
  EXPECT_LE(messages[1].size(), kRoomDatagramBytes);
  json back = minimal();
  back["receivers"] = {json::parse(messages[1]).at("receiver").at("surface")};
  const Scene read = scene_from_json(back, ".");
  for (std::size_t k = 0; k < kMaxLatheProfile; ++k)
    ASSERT_LE(glm::length(read.receivers[0].lathe->profile[k] - scene.receivers[0].lathe->profile[k]), 0.71) << k;
}

TEST(RoomMessages, AScreenAloneIsTheWholePictureAndNoReceiverMessage) {
  const Scene scene = scene_from_json(minimal(), ".");
  const auto messages = room_messages(scene, 1);
  ASSERT_EQ(messages.size(), 1u);
  const json params = json::parse(messages[0]).at("params");
  EXPECT_EQ(params.at("receiver_count"), 0);
  EXPECT_EQ(params.at("tile"), (json{{"x", 0}, {"y", 0}, {"width", scene.render.width}, {"height", scene.render.height}}));
}

}  // namespace
}  // namespace caustic::server
