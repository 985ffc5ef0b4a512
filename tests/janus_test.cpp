// SPDX-License-Identifier: LGPL-2.1-or-later
// Broadcast sessions against a real Janus, run from the shipped
// configuration (janus/, with its ports and secrets filled in), on
// loopback: the mountpoint comes and goes with the session and receives the
// stream; viewer links carry tokens and a pin that Janus checks; only the
// session's holder may change it; a Janus restart gets the mountpoint back;
// a Janus that answers late (frozen, then woken) keeps no mountpoint.
// (Janus gathers no ICE candidates on loopback, so video to browsers is the
// namespace test's: browser_broadcast, tests/browser/broadcast_test.mjs run by
// tests/janus/in_namespace.sh.)
#include "janus_fixture.hpp"

#include "../src/server/janus_requests.hpp"

using namespace caustic::testing::janus_fixture;

TEST_F(Broadcast, TheMountpointLivesWithTheSessionAndReceivesTheStream) {
  const json s = create_broadcast();
  ASSERT_EQ(s.value("mode", ""), "broadcast");
  const auto viewers = http("POST", server_->url() + s["viewers_url"].get<std::string>(), "", "", bearer_token(s["token"]));
  ASSERT_EQ(viewers.status, 201u) << viewers.body;
  const json link = viewers.json();
  const std::uint64_t id = link["mountpoint"];
  // Only causticd knows the secret; the admin key lists private mountpoints.
  const json list = admin({{"request", "list"}});
  ASSERT_TRUE(list.contains("list")) << list.dump();
  json media;
  for (const auto& m : list["list"])
    if (m.value("id", std::uint64_t{0}) == id) media = m["media"];
  ASSERT_EQ(media.size(), 2u) << list.dump();
  const json fed = receiving(id);
  ASSERT_FALSE(fed.is_null()) << "the mountpoint went";
  for (const auto& track : fed["media"]) EXPECT_LT(track.value("age_ms", 1000000), 2000) << track.dump();
  EXPECT_EQ(link["janus_url"], ws_url());
  EXPECT_NE(link["watch_url"].get<std::string>().find("#scene=lens&mountpoint=" + std::to_string(id)), std::string::npos);

  EXPECT_EQ(http("DELETE", server_->url() + s["url"].get<std::string>(), "", "", bearer_token(s["token"])).status, 204u);
  bool gone = false;
  for (int i = 0; i < 50 && !gone; ++i, g_usleep(100000)) {
    gone = true;
    for (const auto& m : admin({{"request", "list"}}).value("list", json::array())) gone &= m.value("id", std::uint64_t{0}) != id;
  }
  EXPECT_TRUE(gone) << "the mountpoint outlived its session";
}

TEST_F(Broadcast, ViewerLinksAreCheckedByJanusAndViewersCannotChangeTheScene) {
  const json s = create_broadcast();
  const json link = http("POST", server_->url() + s["viewers_url"].get<std::string>(), "", "", bearer_token(s["token"])).json();
  JanusClient janus(ws_url());
  ASSERT_TRUE(janus.connected());
  // No token, a forged one, an expired one (signed right, but past): refused.
  EXPECT_EQ(janus.call({{"janus", "create"}}).value("error", json::object()).value("code", 0), 403);
  EXPECT_EQ(janus.call({{"janus", "create"}, {"token", "1999999999,janus,janus.plugin.streaming:AAAA"}})
                .value("error", json::object()).value("code", 0), 403);
  const std::string expired = caustic::server::janus_token(token_secret_, g_get_real_time() / G_USEC_PER_SEC - 10);
  EXPECT_EQ(janus.call({{"janus", "create"}, {"token", expired}}).value("error", json::object()).value("code", 0), 403);
  // The link's token opens a session; the wrong pin gets no stream, the right one an offer.
  const std::string token = link["token"];
  const json created = janus.call({{"janus", "create"}, {"token", token}});
  ASSERT_EQ(created.value("janus", ""), "success") << created.dump();
  const std::uint64_t session = created["data"]["id"];
  const json attached =
      janus.call({{"janus", "attach"}, {"session_id", session}, {"plugin", "janus.plugin.streaming"}, {"token", token}});
  ASSERT_EQ(attached.value("janus", ""), "success") << attached.dump();
  const std::uint64_t handle = attached["data"]["id"];
  auto watch = [&](const std::string& pin) {
    return janus.call({{"janus", "message"}, {"session_id", session}, {"handle_id", handle}, {"token", token},
                       {"body", {{"request", "watch"}, {"id", link["mountpoint"]}, {"pin", pin}}}});
  };
  const json wrong = watch("not-the-pin");
  EXPECT_FALSE(wrong.contains("jsep")) << wrong.dump();
  EXPECT_NE(wrong.dump().find("error"), std::string::npos) << wrong.dump();
  const json right = watch(link["pin"]);
  ASSERT_TRUE(right.contains("jsep")) << right.dump();
  EXPECT_EQ(right["jsep"].value("type", ""), "offer");
  EXPECT_NE(right["jsep"].value("sdp", "").find("VP8/90000"), std::string::npos);

  // A viewer holds the link, not the session's token: no changes, no links.
  const std::string params = server_->url() + s["url"].get<std::string>() + "/params";
  EXPECT_EQ(http("PATCH", params, R"({"object": {"ior": 1.6}})", "application/merge-patch+json", bearer_token(token)).status,
            401u);
  EXPECT_EQ(http("POST", server_->url() + s["viewers_url"].get<std::string>(), "", "", bearer_token(link["pin"])).status,
            401u);
  EXPECT_EQ(http("PATCH", params, R"({"object": {"ior": 1.6}})", "application/merge-patch+json", bearer_token(s["token"])).status,
            200u);
}

TEST_F(Broadcast, AJanusRestartGetsTheMountpointBack) {
  const json s = create_broadcast();
  const json link = http("POST", server_->url() + s["viewers_url"].get<std::string>(), "", "", bearer_token(s["token"])).json();
  const std::uint64_t id = link["mountpoint"];
  janus_.stop();
  ASSERT_TRUE(start_janus()) << "Janus did not come back on its ports";
  json found;
  for (int i = 0; i < 100 && found.is_null(); ++i, g_usleep(100000))
    for (const auto& m : admin({{"request", "list"}}).value("list", json::array()))
      if (m.value("id", std::uint64_t{0}) == id) found = m;
  ASSERT_FALSE(found.is_null()) << "the mountpoint did not come back";
  const json fed = receiving(id);
  ASSERT_FALSE(fed.is_null()) << "the mountpoint went again";
  EXPECT_LT(fed["media"][0].value("age_ms", 1000000), 2000) << "no stream into the new mountpoint";
  // The same link still works: pin and token are unchanged.
  JanusClient janus(ws_url());
  const std::string token = link["token"];
  const json created = janus.call({{"janus", "create"}, {"token", token}});
  ASSERT_EQ(created.value("janus", ""), "success");
  const json attached = janus.call(
      {{"janus", "attach"}, {"session_id", created["data"]["id"]}, {"plugin", "janus.plugin.streaming"}, {"token", token}});
  const json offer = janus.call({{"janus", "message"}, {"session_id", created["data"]["id"]}, {"handle_id", attached["data"]["id"]},
                                 {"token", token}, {"body", {{"request", "watch"}, {"id", id}, {"pin", link["pin"]}}}});
  EXPECT_TRUE(offer.contains("jsep")) << offer.dump();
}

TEST_F(Broadcast, AStoppingServerTakesItsMountpointsWithIt) {
  create_broadcast();
  create_broadcast();
  ASSERT_EQ(admin({{"request", "list"}}).value("list", json::array()).size(), 2u);
  server_->signal(SIGTERM);
  EXPECT_EQ(server_->wait_exit(10000), 0);
  EXPECT_EQ(admin({{"request", "list"}}).value("list", json::array()).size(), 0u) << "mountpoints outlived causticd";
}

TEST_F(Broadcast, BadRequestsAreRefusedAndPlainSessionsHaveNoViewerLinks) {
  EXPECT_EQ(http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "many"})").status, 422u);
  EXPECT_EQ(http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": 3})").status, 422u);
  const json plain = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens"})").json();
  EXPECT_EQ(http("POST", server_->url() + plain["url"].get<std::string>() + "/viewers", "", "", bearer_token(plain["token"])).status,
            409u);
}
