// SPDX-License-Identifier: LGPL-2.1-or-later
// Hardening of sessions: how many an address may hold, a token to create
// them, viewers that must show signs of life, and a viewer that reconnects.
// Each failed against the server before its fix. Black-box over loopback.
#include "hardening_support.hpp"
#include "ws_client.hpp"

#include <unistd.h>

using namespace caustic::testing;

TEST(Hardening, SessionsPerAddressAreLimited) {
  ServerProcess server({"--set", "max_sessions_per_address=1", "--max-sessions", "4"});
  create_session(server);
  const Response r = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab"})");
  EXPECT_EQ(r.status, 429u) << r.body;
  EXPECT_EQ(r.content_type, "application/problem+json");
  EXPECT_EQ(sessions_now(server), 1);
}

TEST(Hardening, SessionCreationCanRequireAToken) {
  const std::string token = "0123456789abcdef0123";
  ServerProcess server({"--set", "session_create_token=" + token});
  const std::string url = server.url() + "/api/v1/sessions";
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})").status, 401u);
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})", "application/json", {{"Authorization", "Bearer nope"}}).status,
            401u);
  // The scheme's case does not matter (RFC 9110 11.1).
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})", "application/json", {{"Authorization", "bearer " + token}}).status,
            201u);
}

TEST(Hardening, ASilentViewerLosesItsSession) {
  ServerProcess server({"--set", "viewer_timeout_s=2"});
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  // It takes the offer and then says nothing: no answer, no RTCP, no ping.
  ASSERT_TRUE(ws_read_text(fd, 20000).has_value());
  EXPECT_TRUE(wait_sessions(server, 0, 2 + 5 + 5)) << "a silent viewer still holds its session";
  ::close(fd);
}

TEST(Hardening, AViewerThatPingsKeepsItsSession) {
  ServerProcess server({"--set", "viewer_timeout_s=2"});
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  for (int i = 0; i < 8; ++i) {  // 4 s, twice the timeout
    ws_send_frame(fd, 1, true, R"({"type": "ping"})");
    g_usleep(500000);
  }
  EXPECT_EQ(sessions_now(server), 1);
  ::close(fd);
}

TEST(Hardening, ASecondSignallingSocketGetsAFreshOffer) {
  ServerProcess server;
  const json s = create_session(server);
  const int first = ws_open(server.port(), signal_path(s));
  ASSERT_GE(first, 0);
  const auto offer1 = ws_read_text(first, 20000);
  ASSERT_TRUE(offer1.has_value());
  EXPECT_EQ(json::parse(*offer1)["type"], "offer");
  const int second = ws_open(server.port(), signal_path(s));
  ASSERT_GE(second, 0);
  std::optional<std::string> message;
  bool offered = false;
  while (!offered && (message = ws_read_text(second, 20000)))
    offered = json::parse(*message, nullptr, false).value("type", "") == "offer";
  EXPECT_TRUE(offered) << "a reconnecting viewer got no offer";
  ::close(first);
  ::close(second);
}
