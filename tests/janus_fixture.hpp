// SPDX-License-Identifier: LGPL-2.1-or-later
// The Broadcast fixture: a real Janus from the shipped configuration (its
// ports and secrets filled in) and causticd pointed at it, on loopback;
// a Janus WebSocket client; the admin API as the tests read it. Shared by
// janus_test.cpp, janus_frozen_test.cpp (Janus frozen with SIGSTOP) and
// janus_leftover_test.cpp (causticd killed).
#pragma once

#include "helper_processes.hpp"
#include "raw_http.hpp"
#include "server_process.hpp"
#include "websocket_listener.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

namespace caustic::testing::janus_fixture {

using caustic::testing::bearer_token;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using caustic::testing::WebSocketListener;
using nlohmann::json;
namespace fs = std::filesystem;
namespace ct = caustic::testing;

// A broadcast asked for on a raw connection, for clients that leave or
// wait on their own terms.
inline std::string broadcast_request() {
  return ct::request_text("POST", "/api/v1/sessions", "Connection: close\r\nContent-Type: application/json\r\n",
                          R"({"scene": "lens", "mode": "broadcast"})");
}

// A Janus WebSocket API client: one request, its answer (events that
// follow an "ack" included), synchronously on the thread-default loop.
class JanusClient {
 public:
  explicit JanusClient(const std::string& url) : ws_(url, "janus-protocol") {}
  bool connected() const { return ws_.socket != nullptr; }

  // Sends `m` and returns the first answer for its transaction that is not an ack.
  json call(json m, int ms = 10000) {
    const std::string t = std::to_string(++transaction_);
    m["transaction"] = t;
    soup_websocket_connection_send_text(ws_.socket, m.dump().c_str());
    json found;
    ws_.spin(
        [&] {
          for (auto it = ws_.messages.begin(); it != ws_.messages.end(); ++it) {
            const json answer = json::parse(*it, nullptr, false);
            if (answer.is_object() && answer.value("transaction", "") == t && answer.value("janus", "") != "ack") {
              found = answer;
              ws_.messages.erase(it);
              return true;
            }
          }
          return false;
        },
        ms);
    return found;
  }

 private:
  WebSocketListener ws_;
  int transaction_ = 0;
};

class Broadcast : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string janus = ct::find_program("janus");
    if (janus.empty()) GTEST_SKIP() << "janus is not installed (tools/bootstrap.sh installs it)";
    dir_ = fs::temp_directory_path() / ("causticd_janus_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // As the package does at install: secrets made once, shared by
    // Janus's files and causticd's environment (the units' EnvironmentFile=).
    std::string output;
    ASSERT_EQ(ct::run_command(std::string(CAUSTIC_JANUS_DIR "/setup-broadcast ") + dir_.string(), &output), 0) << output;
    std::istringstream env(ct::read_file(dir_ / "broadcast.env"));
    for (std::string line; std::getline(env, line);)
      if (const auto eq = line.find('='); line.rfind("CAUSTICD_", 0) == 0 && eq != std::string::npos)
        environment_.emplace_back(line.substr(0, eq), line.substr(eq + 1));
    for (const auto& [key, value] : environment_)
      (key == "CAUSTICD_JANUS_ADMIN_SECRET" ? admin_secret_ : key == "CAUSTICD_JANUS_STREAMING_KEY" ? streaming_key_ : token_secret_) =
          value;
    ASSERT_EQ(admin_secret_.size(), 32u);
    janus_dir_ = dir_ / "janus";
    // The streaming plugin's RTP ports from a block of this test's own: Janus
    // gives a mountpoint's RTCP the port after its RTP port only when that
    // one is free, and the Janus instances of tests run side by side, on the
    // shipped range, took each other's (causticd refuses such ports).
    const std::string range = ct::free_udp_block(64);
    ASSERT_FALSE(range.empty()) << "no block of free UDP ports";
    std::string streaming = ct::read_file(janus_dir_ / "janus.plugin.streaming.jcfg");
    ct::replace_all(streaming, "rtp_port_range = \"31000-31999\"", "rtp_port_range = \"" + range + "\"");
    ASSERT_NE(streaming.find(range), std::string::npos) << "the shipped streaming plugin's range moved";
    std::ofstream(janus_dir_ / "janus.plugin.streaming.jcfg") << streaming;
    // Ports of this test's own, picked free; another process may take one
    // before Janus binds it, so Janus must be seen answering on both.
    std::map<std::string, std::string> shipped;
    for (const char* name : {"janus.transport.http.jcfg", "janus.transport.websockets.jcfg"})
      shipped[name] = ct::read_file(janus_dir_ / name);
    bool ours = false;
    for (int attempt = 0; attempt < 3 && !ours; ++attempt) {
      admin_port_ = ct::free_port();
      do ws_port_ = ct::free_port();
      while (ws_port_ == admin_port_);
      for (const auto& [name, from, to] : {std::tuple{"janus.transport.http.jcfg", "admin_port = 7088", admin_port_},
                                           std::tuple{"janus.transport.websockets.jcfg", "ws_port = 8188", ws_port_}}) {
        std::string text = shipped[name];
        ct::replace_all(text, from, std::string(from).substr(0, std::string(from).find('=') + 2) + std::to_string(to));
        std::ofstream(janus_dir_ / name) << text;
      }
      ours = start_janus();
      if (!ours) janus_.stop();
    }
    ASSERT_TRUE(ours) << "Janus did not answer on the ports picked for it (three tries)";
    server_ = start_server();
    ASSERT_FALSE(server_->url().empty());
  }
  // causticd pointed at this Janus; `extra` arguments added, its log
  // appended to `log` when named.
  std::unique_ptr<ServerProcess> start_server(const std::vector<std::string>& extra = {}, const fs::path& log = {}) {
    std::vector<std::string> args{"--width", "320", "--height", "240", "--set",
                                  "janus_admin_url=http://127.0.0.1:" + std::to_string(admin_port_) + "/admin", "--set",
                                  "janus_ws_url=" + ws_url(), "--set", "viewer_link_ttl_s=60", "--set", "drain_timeout_s=0"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<std::string> wrapper;
    if (!log.empty()) wrapper = {"sh", "-c", "exec \"$@\" 2>>" + log.string(), "sh"};
    return std::make_unique<ServerProcess>(args, environment_, CAUSTICD_BINARY, wrapper);
  }
  void TearDown() override {
    server_.reset();
    janus_.stop();
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  // Whether this Janus answers on both ports: its admin API with this
  // test's secrets, and a Janus WebSocket (something else may hold a port).
  bool start_janus() {
    janus_.start({ct::find_program("janus"), "-F", janus_dir_.string(), "-C", (janus_dir_ / "janus.jcfg").string(), "-o", "-d", "2"});
    if (!ct::raw_wait_listening(admin_port_) || !ct::raw_wait_listening(ws_port_)) return false;
    bool answers = false;
    for (int i = 0; i < 50 && !answers; ++i, g_usleep(100000)) answers = admin({{"request", "list"}}).contains("list");
    return answers && JanusClient(ws_url()).call({{"janus", "info"}}).value("janus", "") == "server_info";
  }
  std::string ws_url() const { return "ws://127.0.0.1:" + std::to_string(ws_port_) + "/"; }

  // A streaming plugin request through Janus's admin API; null if Janus does not answer.
  json admin(json request) {
    request["admin_key"] = streaming_key_;
    const auto r = http("POST", "http://127.0.0.1:" + std::to_string(admin_port_) + "/admin",
                                  json{{"janus", "message_plugin"}, {"transaction", "t"}, {"admin_secret", admin_secret_},
                                       {"plugin", "janus.plugin.streaming"}, {"request", request}}
                                      .dump());
    return r.status == 200 ? r.json().value("response", json()) : json();
  }
  // The mountpoint's info, or its error.
  json info(std::uint64_t id, const std::string& secret) { return admin({{"request", "info"}, {"id", id}, {"secret", secret}}); }

  // Mountpoint `id` as listed once every one of its tracks has had data
  // within the last 2 s (video, and frame messages: a keep-alive a second
  // while still), or as last seen after 10 s of asking (null if never listed).
  json receiving(std::uint64_t id) {
    json seen;
    for (int i = 0; i < 100; ++i, g_usleep(100000))
      for (const auto& m : admin({{"request", "list"}}).value("list", json::array())) {
        if (m.value("id", std::uint64_t{0}) != id) continue;
        seen = m;
        bool fresh = !m.value("media", json::array()).empty();
        for (const auto& track : m["media"]) fresh = fresh && track.value("age_ms", 1000000) < 2000;
        if (fresh) return m;
      }
    return seen;
  }

  // Whether a request to Janus's admin port waits unread (Janus frozen):
  // a connection to it with bytes in its receive queue (/proc/net/tcp).
  bool janus_asked() const {
    std::ifstream table("/proc/net/tcp");
    std::string line;
    std::getline(table, line);  // the header
    while (std::getline(table, line)) {
      std::istringstream row(line);
      std::string slot, local, remote, state, queues;
      row >> slot >> local >> remote >> state >> queues;
      const auto port = std::stoul(local.substr(local.find(':') + 1), nullptr, 16);
      if (port == static_cast<unsigned long>(admin_port_) && state == "01" &&
          std::stoul(queues.substr(queues.find(':') + 1), nullptr, 16) > 0)
        return true;
    }
    return false;
  }

  json create_broadcast() {
    const auto r = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "broadcast"})");
    EXPECT_EQ(r.status, 201u) << r.body;
    return r.json();
  }

  fs::path dir_, janus_dir_;
  std::vector<std::pair<std::string, std::string>> environment_;  // broadcast.env's secrets
  std::string admin_secret_, streaming_key_, token_secret_;
  int admin_port_ = 0, ws_port_ = 0;
  ct::ChildProcess janus_;
  std::unique_ptr<ServerProcess> server_;
};

}  // namespace caustic::testing::janus_fixture
