// SPDX-License-Identifier: LGPL-2.1-or-later
// causticd as a systemd service reloading on SIGHUP: the gallery and the
// configuration read again under running sessions, requests answered
// meanwhile, a broken configuration kept out and the keys that wait for a
// restart named. Every wait is bounded; traffic stays on 127.0.0.1.
#include "service_support.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

using caustic::testing::bearer;
using caustic::testing::create_session;
using caustic::testing::http;
using caustic::testing::NotifySocket;
using caustic::testing::scene_folder;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> scene_ids(const std::string& url) {
  std::vector<std::string> ids;
  const json body = http("GET", url + "/api/v1/scenes").json();  // kept: the loop walks into it
  for (const auto& s : body["scenes"]) ids.push_back(s["id"]);
  return ids;
}

}  // namespace

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
