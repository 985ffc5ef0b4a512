// SPDX-License-Identifier: LGPL-2.1-or-later
// causticd as a systemd service, tested as a plain process: sd_notify
// readiness and watchdog on a test NOTIFY_SOCKET, SIGTERM with open
// sessions (drained or not) and the log lines of a session (SIGHUP reloads:
// service_reload_test.cpp; what check-config and serve refuse:
// serve_cli_test.cpp). Every wait is bounded; traffic stays on 127.0.0.1.
#include "service_support.hpp"
#include "websocket_listener.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

using caustic::testing::bearer;
using caustic::testing::bearer_token;
using caustic::testing::create_session;
using caustic::testing::http;
using caustic::testing::NotifySocket;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

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
using Listener = caustic::testing::WebSocketListener;

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
