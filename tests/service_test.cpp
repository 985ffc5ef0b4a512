// SPDX-License-Identifier: LGPL-2.1-or-later
// causticd as a systemd service, tested as a plain process: sd_notify
// readiness and watchdog on a test NOTIFY_SOCKET, SIGTERM with open
// sessions, SIGHUP reloading the gallery under a running session (what
// check-config and serve refuse: serve_cli_test.cpp). Every wait is
// bounded; traffic stays on 127.0.0.1.
#include "server_process.hpp"

#include <gio/gunixsocketaddress.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <fstream>
#include <regex>
#include <sstream>

using caustic::testing::bearer;
using caustic::testing::bearer_token;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// The receiving end of sd_notify: a Unix datagram socket.
class NotifySocket {
 public:
  explicit NotifySocket(const fs::path& path) : path_(path) {
    fs::remove(path_);
    socket_ = g_socket_new(G_SOCKET_FAMILY_UNIX, G_SOCKET_TYPE_DATAGRAM, G_SOCKET_PROTOCOL_DEFAULT, nullptr);
    GSocketAddress* address = g_unix_socket_address_new(path_.c_str());
    EXPECT_TRUE(g_socket_bind(socket_, address, TRUE, nullptr));
    g_object_unref(address);
  }
  ~NotifySocket() {
    g_object_unref(socket_);
    fs::remove(path_);
  }
  /// The next datagram, or "" after `ms` milliseconds without one.
  std::string next(int ms) {
    g_socket_set_timeout(socket_, 0);
    GCancellable* none = nullptr;
    if (!g_socket_condition_timed_wait(socket_, G_IO_IN, static_cast<gint64>(ms) * 1000, none, nullptr)) return "";
    char buf[4096];
    const gssize n = g_socket_receive(socket_, buf, sizeof buf, nullptr, nullptr);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "";
  }
  /// Waits up to `ms` for a datagram containing `what`.
  bool wait_for(const std::string& what, int ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
      matched_ = next(static_cast<int>(std::max<long long>(1, left.count())));
      if (matched_.find(what) != std::string::npos) return true;
    }
    return false;
  }
  /// The datagram wait_for() found (or the last one it saw).
  const std::string& matched() const { return matched_; }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  std::string matched_;
  GSocket* socket_ = nullptr;
};

// A scene folder with copies of built-in scenes whose mesh paths are absolute.
fs::path scene_folder(const std::string& name, std::initializer_list<const char*> scenes) {
  const fs::path dir = fs::temp_directory_path() / ("causticd_service_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* id : scenes) {
    json j = json::parse(std::ifstream(std::string(CAUSTIC_ASSET_DIR) + "/scenes/" + id + ".json"));
    j["mesh"] = std::string(CAUSTIC_ASSET_DIR) + "/meshes/" + id + ".obj";
    std::ofstream(dir / (std::string(id) + ".json")) << j.dump();
  }
  return dir;
}

json create_session(const std::string& url, const std::string& scene) {
  const auto r = http("POST", url + "/api/v1/sessions", json{{"scene", scene}, {"codec", "vp8"}}.dump());
  EXPECT_EQ(r.status, 201u) << r.body;
  return r.json();
}

std::vector<std::string> scene_ids(const std::string& url) {
  std::vector<std::string> ids;
  const json body = http("GET", url + "/api/v1/scenes").json();  // kept: the loop walks into it
  for (const auto& s : body["scenes"]) ids.push_back(s["id"]);
  return ids;
}

}  // namespace

TEST(Service, ReadyOnlyOnceListeningThenWatchdogPings) {
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_ready.sock");
  ServerProcess server({}, {{"NOTIFY_SOCKET", notify.path().string()}, {"WATCHDOG_USEC", "400000"},
                           {"CAUSTICD_STALL_TIMEOUT_S", "2"}});
  ASSERT_FALSE(server.url().empty());
  ASSERT_TRUE(notify.wait_for("READY=1", 10000));
  // READY=1 promises a listening server with a GL context behind it.
  const json health = http("GET", server.url() + "/api/v1/health").json();
  EXPECT_EQ(health["status"], "ok");
  // Pings at half of WATCHDOG_USEC: several within 2 s, also with a session
  // whose viewer never came, past the 2 s stall limit (its render thread is
  // idle, not stuck; its pipeline waits for a peer).
  const json session = create_session(server.url(), "lens");
  notify.wait_for("never", 2500);
  int pings = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < end) pings += notify.next(500).find("WATCHDOG=1") != std::string::npos;
  EXPECT_GE(pings, 3);
}

// A viewer's signalling socket that only listens.
struct Listener {
  SoupSession* http = soup_session_new();
  SoupWebsocketConnection* socket = nullptr;
  std::vector<std::string> messages;

  explicit Listener(const std::string& ws_url) {
    SoupMessage* msg = soup_message_new("GET", ws_url.c_str());
    soup_session_websocket_connect_async(
        http, msg, nullptr, nullptr, G_PRIORITY_DEFAULT, nullptr,
        [](GObject* source, GAsyncResult* result, gpointer data) {
          auto* self = static_cast<Listener*>(data);
          self->socket = soup_session_websocket_connect_finish(SOUP_SESSION(source), result, nullptr);
          if (!self->socket) return;
          g_signal_connect(self->socket, "message",
                           G_CALLBACK(+[](SoupWebsocketConnection*, gint, GBytes* bytes, gpointer me) {
                             gsize size = 0;
                             const auto* text = static_cast<const char*>(g_bytes_get_data(bytes, &size));
                             static_cast<Listener*>(me)->messages.emplace_back(text, size);
                           }),
                           self);
        },
        this);
    g_object_unref(msg);
    spin([&] { return socket != nullptr; }, 5000);
  }
  ~Listener() {
    if (socket) g_object_unref(socket);
    g_object_unref(http);
  }
  bool spin(const std::function<bool()>& done, int ms) {
    for (int waited = 0; waited < ms && !done(); waited += 10) {
      while (g_main_context_iteration(nullptr, FALSE)) {
      }
      g_usleep(10000);
    }
    return done();
  }
  bool heard(const std::string& what) const {
    for (const auto& m : messages)
      if (m.find(what) != std::string::npos) return true;
    return false;
  }
};

TEST(Service, WithoutDrainSigtermClosesOpenSessionsAndExitsZeroWithoutWaitingForThem) {
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_term.sock");
  ServerProcess server({"--set", "drain_timeout_s=0"}, {{"NOTIFY_SOCKET", notify.path().string()}});
  ASSERT_TRUE(notify.wait_for("READY=1", 10000));
  const json viewed = create_session(server.url(), "lens");
  create_session(server.url(), "wavy");
  Listener viewer("ws" + server.url().substr(4) + viewed["signal_url"].get<std::string>());
  ASSERT_NE(viewer.socket, nullptr);
  viewer.spin([&] { return viewer.heard("offer"); }, 10000);  // the session is live
  const auto start = std::chrono::steady_clock::now();
  server.signal(SIGTERM);
  EXPECT_TRUE(notify.wait_for("STOPPING=1", 10000));
  // The sessions never end by themselves: a server that drained them would
  // still run at this bound (the default drain is 60 s). Closing two
  // pipelines takes under a second when idle; the bound is what a loaded
  // machine may take, not a speed asserted.
  const int status = server.wait_exit(30000);
  std::printf("exited %.1f s after SIGTERM\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  EXPECT_EQ(status, 0);
  // The connected viewer was told before the server went.
  EXPECT_TRUE(viewer.spin([&] { return viewer.heard("\"bye\""); }, 5000));
}

TEST(Service, ASocketReplacedByASecondConnectionIsToldWhy) {
  ServerProcess server;
  const json viewed = create_session(server.url(), "lens");
  const std::string url = "ws" + server.url().substr(4) + viewed["signal_url"].get<std::string>();
  Listener first(url);
  ASSERT_NE(first.socket, nullptr);
  first.spin([&] { return first.heard("offer"); }, 10000);
  Listener second(url);
  ASSERT_NE(second.socket, nullptr);
  EXPECT_TRUE(first.spin([&] { return first.heard(R"("reason":"replaced by a new connection")"); }, 5000));
}

// Draining: the first SIGTERM refuses new sessions (a proxy sends them
// elsewhere) while running ones go on; the last one ending stops the server,
// and so does a second signal.
TEST(Service, SigtermDrainsUntilTheLastSessionEnds) {
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_drain.sock");
  ServerProcess server({}, {{"NOTIFY_SOCKET", notify.path().string()}});
  ASSERT_TRUE(notify.wait_for("READY=1", 10000));
  const json viewed = create_session(server.url(), "lens");
  const json other = create_session(server.url(), "wavy");
  Listener viewer("ws" + server.url().substr(4) + viewed["signal_url"].get<std::string>());
  ASSERT_NE(viewer.socket, nullptr);
  viewer.spin([&] { return viewer.heard("offer"); }, 10000);
  server.signal(SIGTERM);
  EXPECT_TRUE(notify.wait_for("STOPPING=1\nSTATUS=draining: 2 sessions", 10000));
  // The stop's timeout grows by the drain (60 s by default) and its close:
  // the unit's TimeoutStopSec does not cut a longer drain_timeout_s short.
  EXPECT_NE(notify.matched().find("\nEXTEND_TIMEOUT_USEC=90000000"), std::string::npos) << notify.matched();
  const auto health = http("GET", server.url() + "/api/v1/health");
  EXPECT_EQ(health.status, 503u);
  EXPECT_EQ(health.json()["status"], "draining");
  EXPECT_EQ(health.json()["free_sessions"], 0);
  const auto refused = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "lens"})");
  EXPECT_EQ(refused.status, 503u) << refused.body;
  EXPECT_NE(refused.body.find("stopping"), std::string::npos) << refused.body;
  // The running sessions go on: a patch, and the viewer is not told to go.
  const auto patched = http("PATCH", server.url() + viewed["url"].get<std::string>() + "/params",
                            R"({"object": {"ior": 1.6}})", "application/merge-patch+json", bearer(viewed));
  EXPECT_EQ(patched.status, 200u) << patched.body;
  EXPECT_FALSE(viewer.spin([&] { return viewer.heard("\"bye\""); }, 1000));
  EXPECT_EQ(server.wait_exit(500), -1) << "exited while sessions were running";
  // Both end: the server follows.
  EXPECT_EQ(http("DELETE", server.url() + other["url"].get<std::string>(), "", "", bearer(other)).status, 204u);
  EXPECT_EQ(http("DELETE", server.url() + viewed["url"].get<std::string>(), "", "", bearer(viewed)).status, 204u);
  EXPECT_EQ(server.wait_exit(30000), 0);
}

TEST(Service, ASecondSigtermOrTheDrainTimeoutEndsTheDrain) {
  for (const bool second_signal : {true, false}) {
    ServerProcess server({"--set", second_signal ? "drain_timeout_s=600" : "drain_timeout_s=1"});
    const json s = create_session(server.url(), "lens");
    // A session that streams (its first picture rendered), as in a drain
    // that matters: stopping one still starting is another case.
    for (int i = 0; i < 300 && http("GET", server.url() + s["url"].get<std::string>() + "/frame.png", "", "", bearer(s))
                                       .status != 200;
         ++i)
      g_usleep(100000);
    server.signal(SIGTERM);
    for (int i = 0; i < 500 && http("GET", server.url() + "/api/v1/health").status != 503; ++i) g_usleep(20000);
    EXPECT_EQ(http("GET", server.url() + "/api/v1/health").json()["status"], "draining");
    if (second_signal) server.signal(SIGTERM);
    // Far below the 600 s drain, and a drain that never timed out would
    // never end (the session does not); room for a loaded machine's close.
    EXPECT_EQ(server.wait_exit(30000), 0) << (second_signal ? "second signal" : "timeout");
  }
}

TEST(Service, SighupAddsASceneWithoutDroppingTheRunningSession) {
  const fs::path scenes = scene_folder("hup", {"lens"});
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_hup.sock");
  ServerProcess server({"--scenes-dir", scenes.string()}, {{"NOTIFY_SOCKET", notify.path().string()}});
  ASSERT_TRUE(notify.wait_for("READY=1", 10000));
  EXPECT_EQ(scene_ids(server.url()), std::vector<std::string>{"lens"});
  const json session = create_session(server.url(), "lens");
  const std::string params = server.url() + "/api/v1/sessions/" + session["id"].get<std::string>() + "/params";
  const auto auth = bearer(session);

  scene_folder("hup_extra", {"wavy"});
  fs::copy_file(fs::temp_directory_path() / "causticd_service_hup_extra" / "wavy.json", scenes / "wavy.json");
  server.signal(SIGHUP);
  EXPECT_TRUE(notify.wait_for("RELOADING=1", 5000));
  EXPECT_TRUE(notify.wait_for("READY=1", 60000));
  EXPECT_EQ(scene_ids(server.url()), (std::vector<std::string>{"lens", "wavy"}));
  // The session lives on and still takes patches.
  const auto patched = http("PATCH", params, R"({"object": {"ior": 1.6}})", "application/merge-patch+json", auth);
  EXPECT_EQ(patched.status, 200u) << patched.body;
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").json()["sessions"], 1);
  // A gallery that loses every scene is not taken: the old one stays.
  fs::remove(scenes / "lens.json");
  fs::remove(scenes / "wavy.json");
  server.signal(SIGHUP);
  EXPECT_TRUE(notify.wait_for("READY=1", 60000));
  EXPECT_EQ(scene_ids(server.url()), (std::vector<std::string>{"lens", "wavy"}));
  EXPECT_EQ(server.wait_exit(0), -1);  // still running
}

TEST(Service, RequestsAreAnsweredWhileTheGalleryReloads) {
  // Eight scenes: re-reading meshes and drawing thumbnails takes seconds.
  const fs::path scenes = scene_folder("reload_busy", {"lens", "slab", "cylinder", "wavy"});
  for (const char* id : {"lens", "slab", "cylinder", "wavy"})
    fs::copy_file(scenes / (std::string(id) + ".json"), scenes / (std::string(id) + "-b.json"));
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_busy.sock");
  ServerProcess server({"--scenes-dir", scenes.string()}, {{"NOTIFY_SOCKET", notify.path().string()}});
  ASSERT_TRUE(notify.wait_for("READY=1", 30000));
  server.signal(SIGHUP);
  ASSERT_TRUE(notify.wait_for("RELOADING=1", 5000));
  // Answered from the old gallery while the new one is drawn: READY=1,
  // sent once the reload is over, has not come yet. (A reload on the main
  // loop sent it before this request could even be read.)
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
  EXPECT_EQ(scene_ids(server.url()).size(), 8u);
  EXPECT_EQ(notify.next(0), "") << "the reload finished before a request was answered";
  EXPECT_TRUE(notify.wait_for("READY=1", 60000));
  fs::remove_all(scenes);
}

TEST(Service, ASighupWhileTheGalleryLoadsWaitsForTheServer) {
  // A slow gallery (a pool warmed up for a minute of water at 256², some
  // 6 s idle), and a SIGHUP 2 s after the start: its default action once
  // ended the server before it listened (and systemd took that exit as clean).
  const fs::path dir = scene_folder("hup_start", {});
  json pool = json::parse(std::ifstream(std::string(CAUSTIC_ASSET_DIR) + "/scenes/pool.json"));
  pool["water"]["grid"] = 256;
  pool["water"]["warmup_s"] = 60;
  std::ofstream(dir / "pool.json") << pool.dump();
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_hup_start.sock");
  ServerProcess server({"--scenes-dir", dir.string()}, {{"NOTIFY_SOCKET", notify.path().string()}}, CAUSTICD_BINARY,
                       {"sh", "-c", "(sleep 2; kill -HUP $$) & exec \"$@\"", "sh"});
  ASSERT_FALSE(server.url().empty()) << "a SIGHUP during the start ended the server";
  // Ready, then the reload the signal asked for (the configuration may have changed since it was read).
  ASSERT_TRUE(notify.wait_for("READY=1", 60000));
  EXPECT_TRUE(notify.wait_for("RELOADING=1", 60000));
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Service, AReloadNamesTheKeysThatWaitForARestart) {
  // The design queue's keys were once dropped by a reload without a word.
  const fs::path dir = scene_folder("restart_keys", {"lens"});
  const fs::path conf = dir / "causticd.conf", log = dir / "log.txt";
  std::ofstream(conf) << "design_resolution = 128\nmax_sessions = 3\n";
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_restart_keys.sock");
  ServerProcess server({"--config", conf.string(), "--scenes-dir", dir.string()},
                       {{"NOTIFY_SOCKET", notify.path().string()}}, CAUSTICD_BINARY,
                       {"sh", "-c", "exec \"$@\" 2>>" + log.string(), "sh"});
  ASSERT_TRUE(notify.wait_for("READY=1", 60000));
  // Janus's admin client is made at the start too (a broadcast then found
  // it missing although the reload had set its address).
  std::ofstream(conf) << "design_resolution = 64\nmax_sessions = 3\ndesign_max_stored = 5\n"
                         "janus_admin_url = http://127.0.0.1:7088/admin\njanus_admin_secret = 0123456789abcdef\n"
                         "janus_streaming_key = 0123456789abcdef\njanus_token_secret = 0123456789abcdef\n"
                         "janus_ws_url = /janus\n";
  server.signal(SIGHUP);
  ASSERT_TRUE(notify.wait_for("READY=1", 60000));
  std::stringstream text;
  text << std::ifstream(log).rdbuf();
  EXPECT_NE(text.str().find("kept as they were until the next restart: design_resolution, design_max_stored, "
                            "janus_admin_url, janus_admin_secret, janus_streaming_key"),
            std::string::npos)
      << text.str();
}

TEST(Service, SighupRereadsTheConfigurationAndKeepsItWhenBroken) {
  const fs::path dir = scene_folder("conf", {"lens"});
  const fs::path conf = dir / "causticd.conf";
  std::ofstream(conf) << "max_sessions = 1\n";
  NotifySocket notify(fs::temp_directory_path() / "causticd_notify_conf.sock");
  ServerProcess server({"--config", conf.string()}, {{"NOTIFY_SOCKET", notify.path().string()}});
  ASSERT_TRUE(notify.wait_for("READY=1", 10000));
  create_session(server.url(), "lens");
  const auto post = [&] {
    return http("POST", server.url() + "/api/v1/sessions", json{{"scene", "lens"}}.dump()).status;
  };
  EXPECT_EQ(post(), 503u);
  std::ofstream(conf) << "max_sessions = 2\n";
  server.signal(SIGHUP);
  // A reload rebuilds the gallery (thumbnails, the pool's warm-up): some 8 s
  // on an idle 2-core machine, several times that beside other tests.
  ASSERT_TRUE(notify.wait_for("READY=1", 60000));
  EXPECT_EQ(post(), 201u);
  std::ofstream(conf) << "max_sessions = many\n";
  server.signal(SIGHUP);
  ASSERT_TRUE(notify.wait_for("READY=1", 60000));
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").json()["sessions"], 2);  // nothing dropped
  EXPECT_EQ(post(), 503u);  // still 2, not reset
}

TEST(Logs, SessionEventsNameTheSessionSceneCodecAndPeer) {
  // Outside systemd (stderr neither the journal nor a terminal): one line
  // per event with the syslog prefix and the context journald would get as
  // CAUSTICD_SESSION, CAUSTICD_SCENE, CAUSTICD_CODEC and CAUSTICD_PEER.
  const fs::path log = fs::temp_directory_path() / ("causticd_log_" + std::to_string(getpid()) + ".txt");
  fs::remove(log);
  std::string id;
  {
    ServerProcess server({}, {{"JOURNAL_STREAM", "1:1"}},  // a stale variable must not fool it
                         CAUSTICD_BINARY, {"sh", "-c", "exec \"$@\" 2>>" + log.string(), "sh"});
    ASSERT_FALSE(server.url().empty());
    const json session = create_session(server.url(), "lens");
    id = session.value("id", "");
    ASSERT_FALSE(id.empty());
    const std::string token = session["token"];
    EXPECT_EQ(http("DELETE", server.url() + "/api/v1/sessions/" + id, "", "", bearer_token(token)).status,
              204u);
  }
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string context = " [session=" + id + " scene=lens codec=vp8 peer=127.0.0.1]";
  EXPECT_NE(text.find("<6>session " + id + " started: scene lens, vp8" + context + "\n"), std::string::npos) << text;
  EXPECT_NE(text.find("<6>session " + id + " ended: "), std::string::npos) << text;
  // Every line is an event of the server's log, none a library's raw warning.
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    EXPECT_TRUE(std::regex_search(line, std::regex("^<[3-7]>"))) << line;
  fs::remove(log);
}
