// SPDX-License-Identifier: LGPL-2.1-or-later
// Two causticd instances behind each shipped proxy configuration (proxy/):
// new sessions spread by free capacity, every request and the signalling
// WebSocket of a session land on its instance (a viewer gets video), and a stopped instance
// drains (its running sessions go on, new ones go to the other) and then
// exits. The proxies run as plain processes on loopback ports; the shipped
// files are used as they are, with only addresses and ports replaced.
#include "held_ports.hpp"
#include "helper_processes.hpp"
#include "raw_http.hpp"
#include "server_process.hpp"
#include "webrtc_peer.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

using caustic::testing::find_program;
using caustic::testing::bearer;
using caustic::testing::http;
using caustic::testing::read_file;
using caustic::testing::replace_all;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;
namespace ct = caustic::testing;

namespace {

// Column `field` of HAProxy's "show stat" for `server` of `backend`, asked
// on its stats socket ("" when it does not answer or has no such row).
std::string haproxy_stat(const fs::path& socket_path, const std::string& backend, const std::string& server,
                         const std::string& field) {
  std::istringstream csv(ct::raw_exchange(ct::raw_connect_unix(socket_path), "show stat\n", 5000));
  const auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    return cells;
  };
  std::string line;
  if (!std::getline(csv, line) || line.rfind("# ", 0) != 0) return "";
  const auto header = split(line.substr(2));
  const auto column = std::find(header.begin(), header.end(), field);
  if (column == header.end()) return "";
  while (std::getline(csv, line)) {
    const auto row = split(line);
    const auto at = static_cast<std::size_t>(column - header.begin());
    if (row.size() > at && row[0] == backend && row[1] == server) return row[at];
  }
  return "";
}

struct Instance {
  int agent_port;
  std::unique_ptr<ServerProcess> server;
};

class Proxied : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    const std::string program = find_program(GetParam());
    if (program.empty()) GTEST_SKIP() << GetParam() << " is not installed (tools/bootstrap.sh installs it)";
    gst_init(nullptr, nullptr);
    dir_ = fs::temp_directory_path() / ("causticd_proxy_" + GetParam() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::permissions(dir_, fs::perms::all);
    // Instance 1 holds three sessions, instance 2 one: the spread shows.
    // causticd binds its agent port itself and stops if it cannot.
    for (int n : {1, 2}) {
      std::unique_ptr<ServerProcess> server;
      const int agent = ct::start_on_a_free_port([&](int port) {
        server = ServerProcess::try_start({"--max-sessions", n == 1 ? "3" : "1", "--set",
                                           "instance_index=" + std::to_string(n), "--set",
                                           "agent_port=" + std::to_string(port), "--set", "trusted_proxies=127.0.0.1",
                                           "--set", "max_sessions_per_address=10", "--set", "drain_timeout_s=120",
                                           "--set", "design_resolution=64", "--width", "320", "--height", "240"});
        return !server->url().empty() && ct::holds_port(server->pid(), port);
      });
      ASSERT_NE(agent, 0) << "instance " << n << " did not start with an agent port of its own (three tried)";
      instances_.push_back({agent, std::move(server)});
    }
    const std::string shipped =
        read_file(fs::path(CAUSTIC_PROXY_DIR) / (GetParam() == "haproxy" ? "haproxy.cfg" : "nginx.conf"));
    // What answers on the proxy's port must be this proxy: another test's
    // server there would pass a request check.
    port_ = ct::start_on_a_free_port([&](int port) {
      proxy_.start(proxy_argv(program, shipped, port));
      return ct::comes_to_hold(proxy_, port);
    });
    ASSERT_NE(port_, 0) << GetParam() << " did not hold a port of its own (three tried)";
    ASSERT_EQ(http("GET", url() + "/api/v1/scenes").status, 200u) << GetParam() << " does not answer";
    if (GetParam() == "haproxy") {  // until both agents have reported once
      bool reported = false;
      for (int i = 0; i < 100 && !reported; ++i, g_usleep(100000))
        reported = !agent_said("i1").empty() && !agent_said("i2").empty();
      ASSERT_TRUE(reported) << "HAProxy heard from no capacity agent";
    }
  }
  // The proxy's command line, its configuration (the shipped one, adapted)
  // written for listening on `port`.
  std::vector<std::string> proxy_argv(const std::string& program, std::string config, int port) {
    for (int n : {1, 2}) {
      replace_all(config, "127.0.0.1:808" + std::to_string(n),
                  "127.0.0.1:" + std::to_string(instances_[n - 1].server->port()));
      if (GetParam() == "haproxy")
        replace_all(config, "agent-port 908" + std::to_string(n), "agent-port " + std::to_string(instances_[n - 1].agent_port));
    }
    if (GetParam() == "haproxy") {
      replace_all(config, "bind :80", "bind 127.0.0.1:" + std::to_string(port));
      replace_all(config, "log /dev/log local0", "log stderr local0");
      // The test's own view of what the agents told HAProxy.
      replace_all(config, "    maxconn 4096", "    maxconn 4096\n    stats socket " + stats_socket().string() + " mode 600");
      std::ofstream(dir_ / "haproxy.cfg") << config;
      return {program, "-db", "-f", (dir_ / "haproxy.cfg").string()};
    } else {
      replace_all(config, "listen 80;", "listen 127.0.0.1:" + std::to_string(port) + ";");
      replace_all(config, "/var/log/nginx/causticd.log", (dir_ / "access.log").string());
      std::ofstream(dir_ / "site.conf") << config;
      std::ofstream(dir_ / "nginx.conf") << "daemon off;\nworker_processes 1;\npid " << (dir_ / "nginx.pid").string()
                                         << ";\nerror_log stderr warn;\nevents {}\nhttp {\n  client_body_temp_path "
                                         << (dir_ / "body").string() << ";\n  proxy_temp_path "
                                         << (dir_ / "proxy").string() << ";\n  include " << (dir_ / "site.conf").string()
                                         << ";\n}\n";
      return {program, "-p", dir_.string(), "-c", (dir_ / "nginx.conf").string()};
    }
  }
  fs::path stats_socket() const { return dir_ / "haproxy.sock"; }
  // What instance `server`'s capacity agent last told HAProxy ("" before it did).
  std::string agent_said(const std::string& server) const {
    return haproxy_stat(stats_socket(), "new_sessions", server, "last_agt");
  }
  void TearDown() override {
    proxy_.stop();
    instances_.clear();
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  // The instance a session's URL names (1 or 2), 0 if none.
  static int instance_of(const json& session) {
    std::smatch m;
    const std::string u = session.value("url", "");
    return std::regex_search(u, m, std::regex("^/i/([0-9]+)/api/v1/sessions/[0-9a-f]{32}$")) ? std::stoi(m[1]) : 0;
  }
  ct::Response create() { return http("POST", url() + "/api/v1/sessions", R"({"scene": "lens", "codec": "vp8"})"); }

  fs::path dir_;
  std::vector<Instance> instances_;
  int port_ = 0;
  ct::ChildProcess proxy_;
};

}  // namespace

TEST_P(Proxied, SessionsSpreadByFreeCapacityAndEveryRequestReachesTheirInstance) {
  std::vector<json> sessions;
  int on[3] = {0, 0, 0};
  for (int i = 0; i < 4; ++i) {
    const auto r = create();
    ASSERT_EQ(r.status, 201u) << "session " << i + 1 << ": " << r.body;
    sessions.push_back(r.json());
    ++on[instance_of(sessions.back())];
  }
  EXPECT_EQ(on[1], 3);
  EXPECT_EQ(on[2], 1);
  EXPECT_EQ(create().status, 503u) << "both instances are full";

  for (const json& s : sessions) {
    const int n = instance_of(s);
    // Only the owner knows the session: any other instance would refuse it.
    const auto params = http("GET", url() + s["url"].get<std::string>() + "/params", "", "", bearer(s));
    EXPECT_EQ(params.status, 200u) << params.body;
    const std::string head = ct::raw_request(port_, "GET", s["url"].get<std::string>() + "/params",
                                             "Authorization: Bearer " + s["token"].get<std::string>() +
                                                 "\r\nConnection: close\r\n");
    EXPECT_EQ(ct::raw_header(head, "X-Causticd-Instance"), std::to_string(n));
    // A viewer: signalling through the proxy to the same instance, media
    // straight from it. Its going away ends the session.
    ct::WebRtcPeer peer("vp8", "ws://127.0.0.1:" + std::to_string(port_) + s["signal_url"].get<std::string>());
    EXPECT_TRUE(peer.wait_for_frames(2, 60)) << "no video from instance " << n << " through " << GetParam() << ": "
                                             << peer.error();
  }
  // A path naming an instance that does not exist goes nowhere.
  EXPECT_EQ(http("GET", url() + "/i/7/api/v1/health").status, 404u);
}

TEST_P(Proxied, AStoppedInstanceDrainsAndNewSessionsGoToTheOther) {
  std::vector<json> first, second;
  for (int i = 0; i < 4; ++i) {
    const auto r = create();
    ASSERT_EQ(r.status, 201u) << r.body;
    (instance_of(r.json()) == 1 ? first : second).push_back(r.json());
  }
  ASSERT_EQ(first.size(), 3u);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(http("DELETE", url() + second[0]["url"].get<std::string>(), "", "", bearer(second[0])).status, 204u);
  ServerProcess& one = *instances_[0].server;
  one.signal(SIGTERM);
  for (int i = 0; i < 50 && http("GET", one.url() + "/api/v1/health").status != 503; ++i) g_usleep(100000);
  ASSERT_EQ(http("GET", one.url() + "/api/v1/health").json()["status"], "draining");
  if (GetParam() == "haproxy") {  // the agent has told HAProxy (nginx learns from the 503s alone)
    std::string status;
    for (int i = 0; i < 100 && status != "DRAIN (agent)"; ++i, g_usleep(100000))
      status = haproxy_stat(stats_socket(), "new_sessions", "i1", "status");
    ASSERT_EQ(status, "DRAIN (agent)") << "HAProxy's view of the draining instance; its agent said " << agent_said("i1");
  }

  // Its running sessions go on, through the proxy.
  for (const json& s : first) {
    const auto patched = http("PATCH", url() + s["url"].get<std::string>() + "/params", R"({"object": {"ior": 1.6}})",
                              "application/merge-patch+json", bearer(s));
    EXPECT_EQ(patched.status, 200u) << patched.body;
  }
  // New sessions go to the other instance, until it is full.
  const auto next = create();
  ASSERT_EQ(next.status, 201u) << next.body;
  EXPECT_EQ(instance_of(next.json()), 2);
  EXPECT_EQ(create().status, 503u);
  EXPECT_EQ(one.wait_exit(500), -1) << "the draining instance left while its sessions ran";
  // Its last session ends: it exits, cleanly.
  for (const json& s : first)
    EXPECT_EQ(http("DELETE", url() + s["url"].get<std::string>(), "", "", bearer(s)).status, 204u);
  EXPECT_EQ(one.wait_exit(10000), 0);
}

// A visitor's design is kept by the instance that made it: its status URL,
// and the viewer's session of it, name that instance.
TEST_P(Proxied, AVisitorsDesignStaysWithTheInstanceThatMadeIt) {
  if (!DESIGN_BUILT_IN) GTEST_SKIP() << "built without the designer";
  const auto png = http("GET", url() + "/api/v1/scenes/lens/thumbnail.png");
  ASSERT_EQ(png.status, 200u);
  const auto upload = http("POST", url() + "/api/v1/designs?name=Lens", png.body, "image/png");
  ASSERT_EQ(upload.status, 202u) << upload.body;
  std::smatch m;
  const std::string status_url = upload.json()["status_url"];
  ASSERT_TRUE(std::regex_match(status_url, m, std::regex("^/i/([12])/api/v1/designs/[0-9a-f]{32}$"))) << status_url;
  const int n = std::stoi(m[1]);
  json design;
  for (int i = 0; i < 600; ++i, g_usleep(200000)) {
    design = http("GET", url() + status_url).json();
    if (design.value("state", "") == "ready" || design.value("state", "") == "failed") break;
  }
  ASSERT_EQ(design.value("state", ""), "ready") << design.dump();
  const std::string home = "/i/" + std::to_string(n);
  EXPECT_EQ(http("GET", url() + home + "/api/v1/scenes/" + design["scene"].get<std::string>()).status, 200u);
  const auto session =
      http("POST", url() + home + "/api/v1/sessions", json{{"scene", design["scene"]}, {"codec", "vp8"}}.dump());
  ASSERT_EQ(session.status, 201u) << session.body;
  EXPECT_EQ(instance_of(session.json()), n);
}

INSTANTIATE_TEST_SUITE_P(ShippedConfigurations, Proxied, ::testing::Values("haproxy", "nginx"));
