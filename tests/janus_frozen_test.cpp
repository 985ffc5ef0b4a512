// SPDX-License-Identifier: LGPL-2.1-or-later
// Broadcasts against a Janus frozen with SIGSTOP (a Janus that answers late
// or not at all): a client that leaves meanwhile, a create answered after
// the server gave up, a server that stops meanwhile, and requests made side
// by side, each leaving no mountpoint in Janus once it wakes.
#include "janus_fixture.hpp"

#include <csignal>

using namespace caustic::testing::janus_fixture;

// Janus frozen as the server stops: the destroys, asked side by side, wait
// in Janus and are carried out when it wakes; the server has gone by then.
TEST_F(Broadcast, AStoppingServerLeavesItsDestroysWithAFrozenJanus) {
  create_broadcast();
  create_broadcast();
  ASSERT_EQ(admin({{"request", "list"}}).value("list", json::array()).size(), 2u);
  janus_.signal(SIGSTOP);
  server_->signal(SIGTERM);
  EXPECT_EQ(server_->wait_exit(30000), 0);
  janus_.signal(SIGCONT);
  json list;
  bool clean = false;
  for (int i = 0; i < 100 && !clean; ++i, g_usleep(100000)) {
    list = admin({{"request", "list"}});
    clean = list.is_object() && list.contains("list") && list["list"].empty();
  }
  EXPECT_TRUE(clean) << "mountpoints outlived causticd: " << list.dump();
}

// A client that leaves while Janus is still answering (frozen here) gets no
// session, and the mountpoint made for it goes.
TEST_F(Broadcast, AClientThatLeavesBeforeJanusAnswersLeavesNothingBehind) {
  janus_.signal(SIGSTOP);
  const int fd = ct::raw_connect(server_->port());
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(ct::raw_send(fd, broadcast_request()));
  bool asked = false;
  for (int i = 0; i < 100 && !asked; ++i, g_usleep(100000)) asked = janus_asked();
  ASSERT_TRUE(asked) << "the server did not ask the frozen Janus";
  ::close(fd);
  g_usleep(500000);  // the server notices
  janus_.signal(SIGCONT);
  // Janus answers the create; the server destroys what it made.
  bool clean = false;
  for (int i = 0; i < 100 && !clean; ++i, g_usleep(100000)) {
    const json list = admin({{"request", "list"}});
    clean = list.is_object() && list.value("list", json::array()).empty();
  }
  EXPECT_TRUE(clean) << admin({{"request", "list"}}).dump();
  EXPECT_EQ(http("GET", server_->url() + "/api/v1/health").json()["sessions"], 0);
  // And the server goes on making broadcasts.
  create_broadcast();
}

// A create that Janus takes only after the server gave up on it (5 s) is
// still carried out when Janus wakes: the server destroys what it asked for.
TEST_F(Broadcast, AMountpointThatJanusMakesAfterTheServerGaveUpGoesAgain) {
  janus_.signal(SIGSTOP);
  const auto r = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "broadcast"})");
  EXPECT_EQ(r.status, 502u) << r.body;
  janus_.signal(SIGCONT);
  // Janus makes the mountpoint as it wakes; it must not stay.
  json list;
  bool clean = false;
  for (int i = 0; i < 150 && !clean; ++i, g_usleep(100000)) {
    list = admin({{"request", "list"}});
    clean = list.is_object() && list.value("list", json::array()).empty();
    if (clean) {  // gone, or not made yet: empty for 3 s running
      for (int j = 0; j < 30 && clean; ++j, g_usleep(100000)) {
        list = admin({{"request", "list"}});
        clean = list.is_object() && list.value("list", json::array()).empty();
      }
    }
  }
  EXPECT_TRUE(clean) << list.dump();
  EXPECT_EQ(http("GET", server_->url() + "/api/v1/health").json()["sessions"], 0);
  create_broadcast();
}

TEST_F(Broadcast, RequestsMadeSideBySideKeepTheLimitPerAddress) {
  // A broadcast waiting for Janus counts as held: of five requests made
  // side by side from one address (its limit is 2), three are refused
  // before Janus answers any, and only two mountpoints are asked for.
  janus_.signal(SIGSTOP);
  std::vector<int> fds;
  for (int i = 0; i < 5; ++i) {
    fds.push_back(ct::raw_connect(server_->port()));
    ASSERT_GE(fds.back(), 0);
    ASSERT_TRUE(ct::raw_send(fds.back(), broadcast_request()));
  }
  // The three beyond the limit are refused while Janus is still frozen:
  // the two before them were counted before it answered either.
  std::vector<std::string> answers(fds.size());
  std::vector<bool> done(fds.size(), false);
  int refused = 0;
  for (int round = 0; round < 100 && refused < 3; ++round)
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (done[i]) continue;
      bool closed = false;
      answers[i] += ct::raw_read_all(fds[i], 20, &closed);
      done[i] = closed;
      refused += closed && ct::raw_status(answers[i]) == 429;
    }
  EXPECT_EQ(refused, 3) << "refused before Janus answered";
  janus_.signal(SIGCONT);
  int created = 0;
  for (std::size_t i = 0; i < fds.size(); ++i) {
    if (!done[i]) answers[i] += ct::raw_read_all(fds[i], 20000);
    created += ct::raw_status(answers[i]) == 201;
    ::close(fds[i]);
  }
  EXPECT_EQ(created, 2);
  EXPECT_EQ(http("GET", server_->url() + "/api/v1/health").json()["sessions"], 2);
  EXPECT_EQ(admin({{"request", "list"}}).value("list", json::array()).size(), 2u);
}
