// SPDX-License-Identifier: LGPL-2.1-or-later
// One instance's side of running behind a proxy: its number in the session
// URLs (and the plain paths still working), another instance's prefix
// refused, X-Forwarded-For believed only from a trusted proxy, ICE
// candidates kept inside the configured port range, and the capacity agent
// telling the proxy its free share and its drain.
#include "held_ports.hpp"
#include "helper_processes.hpp"
#include "raw_http.hpp"
#include "server_process.hpp"
#include "ws_client.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <regex>

using caustic::testing::bearer;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace ct = caustic::testing;

namespace {

unsigned create_from(const std::string& url, const std::string& forwarded_for) {
  return http("POST", url + "/api/v1/sessions", R"({"scene": "lens"})", "application/json",
              {{"X-Forwarded-For", forwarded_for}})
      .status;
}

// The capacity agent's one line (HAProxy's agent-check protocol): it
// speaks first, unasked, and closes.
std::string agent_line(int port) {
  const int fd = ct::raw_connect(port);
  return fd < 0 ? "no agent on port " + std::to_string(port) : ct::raw_exchange(fd, "");
}

}  // namespace

TEST(Instance, TheAgentTellsTheFreeShareAndTheDrain) {
  // The server binds the agent port itself and stops if another process
  // took it since it was picked: then another port.
  std::unique_ptr<ServerProcess> server;
  const int agent = ct::start_on_a_free_port([&](int port) {
    server = ServerProcess::try_start({"--max-sessions", "3", "--set", "agent_port=" + std::to_string(port), "--set",
                                       "max_sessions_per_address=10", "--set", "drain_timeout_s=120"});
    return !server->url().empty() && ct::holds_port(server->pid(), port);
  });
  ASSERT_NE(agent, 0) << "the server did not start with an agent port of its own (three tried)";
  EXPECT_EQ(agent_line(agent), "up ready 100%\n");
  const json s = http("POST", server->url() + "/api/v1/sessions", R"({"scene": "lens"})").json();
  EXPECT_EQ(agent_line(agent), "up ready 67%\n");  // 2 of 3 free
  for (int i = 0; i < 2; ++i) http("POST", server->url() + "/api/v1/sessions", R"({"scene": "lens"})");
  EXPECT_EQ(agent_line(agent), "up ready 0%\n");
  // Stopped with sessions running: it drains, and says so until it leaves.
  server->signal(SIGTERM);
  for (int i = 0; i < 50 && http("GET", server->url() + "/api/v1/health").status != 503; ++i) g_usleep(100000);
  EXPECT_EQ(agent_line(agent), "up drain\n");
}

TEST(Instance, SessionUrlsNameTheInstanceAndAnotherInstancesPrefixIsRefused) {
  ServerProcess server({"--set", "instance_index=3"});
  const auto created = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "lens"})");
  ASSERT_EQ(created.status, 201u) << created.body;
  const json s = created.json();
  const std::string id = s["id"];
  EXPECT_EQ(s["url"], "/i/3/api/v1/sessions/" + id);
  EXPECT_EQ(s["signal_url"].get<std::string>().rfind("/i/3/api/v1/sessions/" + id + "/signal?token=", 0), 0u);
  EXPECT_EQ(http("GET", server.url() + "/i/3/api/v1/sessions/" + id + "/params", "", "", bearer(s)).status, 200u);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/sessions/" + id + "/params", "", "", bearer(s)).status, 200u);
  const auto elsewhere = http("GET", server.url() + "/i/4/api/v1/sessions/" + id + "/params", "", "", bearer(s));
  EXPECT_EQ(elsewhere.status, 421u);
  EXPECT_EQ(elsewhere.content_type, "application/problem+json");
  const json health = http("GET", server.url() + "/i/3/api/v1/health").json();
  EXPECT_EQ(health["instance"], 3);
  EXPECT_EQ(health["free_sessions"], health["max_sessions"].get<int>() - 1);
  const std::string head = ct::raw_request(server.port(), "GET", "/api/v1/health");
  EXPECT_EQ(ct::raw_header(head, "X-Causticd-Instance"), "3");
  // The signalling WebSocket at its prefixed URL; another prefix gets none.
  const int fd = ct::ws_open(server.port(), s["signal_url"]);
  EXPECT_GE(fd, 0);
  if (fd >= 0) ::close(fd);
  std::string other = s["signal_url"];
  other.replace(0, 4, "/i/4");
  EXPECT_LT(ct::ws_open(server.port(), other), 0);
}

TEST(Instance, WithoutANumberUrlsAreThePlainOnes) {
  ServerProcess server;
  const json s = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "lens"})").json();
  EXPECT_EQ(s["url"], "/api/v1/sessions/" + s["id"].get<std::string>());
  EXPECT_FALSE(http("GET", server.url() + "/api/v1/health").json().contains("instance"));
  EXPECT_EQ(http("GET", server.url() + "/i/1/api/v1/health").status, 421u);
}

TEST(Instance, ForwardedForCountsOnlyFromATrustedProxy) {
  // Trusted (loopback is the proxy): each visitor address has its own limit.
  {
    ServerProcess server({"--set", "trusted_proxies=127.0.0.1", "--set", "max_sessions_per_address=1"});
    EXPECT_EQ(create_from(server.url(), "10.0.0.1"), 201u);
    EXPECT_EQ(create_from(server.url(), "192.0.2.7, 10.0.0.2"), 201u);  // the last address is the proxy's word
    EXPECT_EQ(create_from(server.url(), "10.0.0.1"), 429u);
    EXPECT_EQ(create_from(server.url(), "not an address"), 201u);  // counted as the proxy itself
    EXPECT_EQ(create_from(server.url(), "<script>"), 429u);
    // An IPv6 visitor counts as its /64: another address of it is the same visitor.
    EXPECT_EQ(create_from(server.url(), "2001:db8:1:2::1"), 201u);
    EXPECT_EQ(create_from(server.url(), "2001:db8:1:2:abcd::99"), 429u);
    EXPECT_EQ(create_from(server.url(), "2001:db8:1:3::1"), 201u);
  }
  // Not trusted: a client cannot choose its bucket.
  ServerProcess server({"--set", "max_sessions_per_address=1"});
  EXPECT_EQ(create_from(server.url(), "10.0.0.1"), 201u);
  EXPECT_EQ(create_from(server.url(), "10.0.0.2"), 429u);
}

TEST(Instance, IceCandidatesUseOnlyTheConfiguredPorts) {
  // A block of ten free ports: a fixed range could be held by another test's
  // socket, and the server would then find no port to gather from.
  const std::string range = ct::free_udp_block(10);
  ASSERT_FALSE(range.empty()) << "no block of free UDP ports";
  const int first = std::stoi(range);
  ServerProcess server({"--set", "ice_port_range=" + range});
  const json s = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "lens"})").json();
  const int fd = ct::ws_open(server.port(), s["signal_url"]);
  ASSERT_GE(fd, 0);
  int candidates = 0;
  for (int k = 0; k < 40; ++k) {
    const auto text = ct::ws_read_text(fd, 5000);
    if (!text) break;
    const json m = json::parse(*text, nullptr, false);
    if (!m.is_object() || m.value("type", "") != "ice") continue;
    std::smatch port;
    const std::string candidate = m.value("candidate", "");
    // Active TCP candidates name port 9, as RFC 6544 has them: no socket.
    if (candidate.find(" UDP ") == std::string::npos) continue;
    ASSERT_TRUE(std::regex_search(candidate, port, std::regex(" ([0-9]+) typ "))) << candidate;
    EXPECT_GE(std::stoi(port[1]), first) << candidate;
    EXPECT_LE(std::stoi(port[1]), first + 9) << candidate;
    ++candidates;
  }
  ::close(fd);
  EXPECT_GT(candidates, 0) << "no UDP candidate";
}
