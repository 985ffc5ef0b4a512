// SPDX-License-Identifier: LGPL-2.1-or-later
// A receiver shaped by a mesh the scene brings (the gallery's cloth), over
// REST: its geometry comes with the scene for the viewer to draw, its file
// never; a session moves or adds receivers of that shape and can neither
// name another nor list a file, and every refusal leaves the parameters.
#include "rest_fixture.hpp"

#include <chrono>
#include <cmath>

using caustic::testing::bearer;
using caustic::testing::expect_problem;
using caustic::testing::http;
using caustic::testing::Response;
using caustic::testing::Rest;
using nlohmann::json;

TEST_F(Rest, AShapedReceiverComesWithItsSceneAndNeverItsFile) {
  const Response scene = http("GET", server_.url() + "/api/v1/scenes/cloth");
  ASSERT_EQ(scene.status, 200u) << scene.body;
  EXPECT_EQ(scene.body.find(".obj"), std::string::npos) << "a file name leaked";
  const json cloth = scene.json()["receiver_meshes"]["cloth"];
  const auto vertices = cloth["positions"].size() / 3;
  ASSERT_GT(vertices, 3u);
  EXPECT_EQ(cloth["positions"].size(), 3 * vertices);
  EXPECT_EQ(cloth["uvs"].size(), 2 * vertices);
  EXPECT_EQ(cloth["indices"].size() % 3, 0u);
  for (const json& i : cloth["indices"]) ASSERT_LT(i.get<std::size_t>(), vertices);
  for (const json& t : cloth["uvs"]) ASSERT_TRUE(t.get<double>() >= 0 && t.get<double>() <= 1);
  // The list stays light: shapes come with one scene at a time.
  EXPECT_EQ(http("GET", server_.url() + "/api/v1/scenes").body.find("receiver_meshes"), std::string::npos);

  const json s = create("cloth");
  const std::string url = session_url(s) + "/params";
  const Response got = http("GET", url, "", "", bearer(s));
  EXPECT_EQ(got.body.find(".obj"), std::string::npos) << "a file name leaked";
  const json before = got.json();
  EXPECT_FALSE(before["params"].contains("receiver_meshes"));
  ASSERT_EQ(before["params"]["receivers"].size(), 1u);
  EXPECT_EQ(before["params"]["receivers"][0]["mesh"], "cloth");

  const std::string patch_type = "application/merge-patch+json";
  json receivers = before["params"]["receivers"];
  receivers[0]["mesh"] = "bowl";
  const Response other = http("PATCH", url, json{{"receivers", receivers}}.dump(), patch_type, bearer(s));
  expect_problem(other, 422, "receivers[0].mesh");
  EXPECT_NE(other.body.find("receiver_meshes: cloth"), std::string::npos) << other.body;
  EXPECT_EQ(other.body.find("bowl"), std::string::npos) << "what was sent came back: " << other.body;
  for (const char* files : {R"({"receiver_meshes": {"x": "/etc/passwd"}})", R"({"receiver_meshes": null})",
                            R"({"receiver_meshes": {"cloth": "../meshes/cloth.obj"}})"})
    expect_problem(http("PATCH", url, files, patch_type, bearer(s)), 422, "receiver_meshes");
  EXPECT_EQ(http("GET", url, "", "", bearer(s)).json(), before);

  // Moved along the table, and a second one beside it: three surfaces, three tiles.
  receivers[0]["mesh"] = "cloth";
  receivers[0]["center"] = {16, 0, -29.99};
  receivers.push_back(receivers[0]);
  receivers[1]["center"] = {16, 18, -29.99};
  const Response moved = http("PATCH", url, json{{"receivers", receivers}}.dump(), patch_type, bearer(s));
  ASSERT_EQ(moved.status, 200u) << moved.body;
  const json now = http("GET", url, "", "", bearer(s)).json();
  EXPECT_EQ(now["params"]["receivers"][1]["mesh"], "cloth");
  EXPECT_EQ(now["atlas"].size(), 3u);
}

TEST_F(Rest, ASessionSetsItsReceiversAFewTimesAtOnceThenOnceASecond) {
  // Receivers set anew may each build triangles and a search tree on the
  // main loop: seven lathes set at the allowed patch rate once made every
  // other client wait seconds. Eight at once, then two a second; the tally
  // allows for a slow machine. Bounded: 30 patches.
  const json s = create("cloth");
  const std::string url = session_url(s) + "/params", patch_type = "application/merge-patch+json";
  json receivers = http("GET", url, "", "", bearer(s)).json()["params"]["receivers"];
  const auto start = std::chrono::steady_clock::now();
  int accepted = 0;
  Response refused;
  for (int k = 0; k < 30; ++k) {
    receivers[0]["center"] = {16, 0.5 * k, -29.99};
    const Response r = http("PATCH", url, json{{"receivers", receivers}}.dump(), patch_type, bearer(s));
    if (r.status == 429) {
      refused = r;
      break;
    }
    ASSERT_EQ(r.status, 200u) << r.body;
    ++accepted;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int allowed = 8 + static_cast<int>(std::ceil(2 * seconds));
  // A machine so slow that the bucket refilled as fast as it was spent may
  // end the 30 without a refusal; any other must have been refused.
  if (accepted < 30 || allowed < 30) expect_problem(refused, 429, "receivers");
  EXPECT_GE(accepted, 8);
  EXPECT_LE(accepted, allowed);
  // The refused patch changed nothing: the last accepted one stands.
  if (accepted > 0 && accepted < 30) {
    EXPECT_EQ(http("GET", url, "", "", bearer(s)).json()["params"]["receivers"][0]["center"],
              json({16, 0.5 * (accepted - 1), -29.99}));
  }
  // Other patches go on.
  EXPECT_EQ(http("PATCH", url, R"({"object": {"ior": 1.6}})", patch_type, bearer(s)).status, 200u);
}
