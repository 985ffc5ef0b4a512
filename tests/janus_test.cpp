// SPDX-License-Identifier: LGPL-2.1-or-later
// Broadcast sessions against a real Janus, run from the shipped
// configuration (janus/, with its ports and secrets filled in), on
// loopback: the mountpoint comes and goes with the session and receives the
// stream; viewer links carry tokens and a pin that Janus checks; only the
// session's holder may change it; a Janus restart gets the mountpoint back;
// a Janus that answers late (frozen, then woken) keeps no mountpoint.
// (Janus gathers no ICE candidates on loopback, so video to browsers is the
// namespace test's: tests/janus/broadcast_test.sh.)
#include "helper_processes.hpp"
#include "raw_http.hpp"
#include "server_process.hpp"

#include <gtest/gtest.h>

#include "../src/server/broadcast.hpp"

#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>
#include <tuple>

using caustic::testing::bearer_token;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;
namespace ct = caustic::testing;

namespace {

// A broadcast asked for on a raw connection, for clients that leave or
// wait on their own terms.
std::string broadcast_request() {
  return ct::request_text("POST", "/api/v1/sessions", "Connection: close\r\nContent-Type: application/json\r\n",
                          R"({"scene": "lens", "mode": "broadcast"})");
}

// A Janus WebSocket API client: one request, its answer (events that
// follow an "ack" included), synchronously on the thread-default loop.
class JanusClient {
 public:
  explicit JanusClient(const std::string& url) {
    SoupMessage* msg = soup_message_new("GET", url.c_str());
    const char* protocols[] = {"janus-protocol", nullptr};
    soup_session_websocket_connect_async(
        http_, msg, nullptr, const_cast<char**>(protocols), G_PRIORITY_DEFAULT, nullptr,
        [](GObject* source, GAsyncResult* result, gpointer data) {
          auto* self = static_cast<JanusClient*>(data);
          self->socket_ = soup_session_websocket_connect_finish(SOUP_SESSION(source), result, nullptr);
          if (!self->socket_) return;
          g_signal_connect(self->socket_, "message", G_CALLBACK(+[](SoupWebsocketConnection*, gint, GBytes* b, gpointer me) {
                             gsize size = 0;
                             const auto* text = static_cast<const char*>(g_bytes_get_data(b, &size));
                             static_cast<JanusClient*>(me)->inbox_.push_back(json::parse(text, text + size, nullptr, false));
                           }),
                           self);
        },
        this);
    g_object_unref(msg);
    spin([&] { return socket_ != nullptr; }, 5000);
  }
  ~JanusClient() {
    if (socket_) g_object_unref(socket_);
    g_object_unref(http_);
  }
  bool connected() const { return socket_ != nullptr; }

  // Sends `m` and returns the first answer for its transaction that is not an ack.
  json call(json m, int ms = 10000) {
    const std::string t = std::to_string(++transaction_);
    m["transaction"] = t;
    soup_websocket_connection_send_text(socket_, m.dump().c_str());
    json found;
    spin(
        [&] {
          for (auto it = inbox_.begin(); it != inbox_.end(); ++it)
            if (it->value("transaction", "") == t && it->value("janus", "") != "ack") {
              found = *it;
              inbox_.erase(it);
              return true;
            }
          return false;
        },
        ms);
    return found;
  }

 private:
  bool spin(const std::function<bool()>& done, int ms) {
    for (int waited = 0; waited < ms && !done(); waited += 5) {
      while (g_main_context_iteration(nullptr, FALSE)) {
      }
      g_usleep(5000);
    }
    return done();
  }
  SoupSession* http_ = soup_session_new();
  SoupWebsocketConnection* socket_ = nullptr;
  std::vector<json> inbox_;
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
    std::vector<std::pair<std::string, std::string>> environment;
    std::istringstream env(ct::read_file(dir_ / "broadcast.env"));
    for (std::string line; std::getline(env, line);)
      if (const auto eq = line.find('='); line.rfind("CAUSTICD_", 0) == 0 && eq != std::string::npos)
        environment.emplace_back(line.substr(0, eq), line.substr(eq + 1));
    for (const auto& [key, value] : environment)
      (key == "CAUSTICD_JANUS_ADMIN_SECRET" ? admin_secret_ : key == "CAUSTICD_JANUS_STREAMING_KEY" ? streaming_key_ : token_secret_) =
          value;
    ASSERT_EQ(admin_secret_.size(), 32u);
    janus_dir_ = dir_ / "janus";
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
    server_ = std::make_unique<ServerProcess>(
        std::vector<std::string>{"--width", "320", "--height", "240", "--set",
                                 "janus_admin_url=http://127.0.0.1:" + std::to_string(admin_port_) + "/admin", "--set",
                                 "janus_ws_url=" + ws_url(), "--set", "viewer_link_ttl_s=60", "--set", "drain_timeout_s=0"},
        environment);
    ASSERT_FALSE(server_->url().empty());
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
  std::string admin_secret_, streaming_key_, token_secret_;
  int admin_port_ = 0, ws_port_ = 0;
  ct::ChildProcess janus_;
  std::unique_ptr<ServerProcess> server_;
};

}  // namespace

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

TEST_F(Broadcast, BadRequestsAreRefusedAndPlainSessionsHaveNoViewerLinks) {
  EXPECT_EQ(http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "many"})").status, 422u);
  EXPECT_EQ(http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": 3})").status, 422u);
  const json plain = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens"})").json();
  EXPECT_EQ(http("POST", server_->url() + plain["url"].get<std::string>() + "/viewers", "", "", bearer_token(plain["token"])).status,
            409u);
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
