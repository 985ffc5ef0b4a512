// SPDX-License-Identifier: LGPL-2.1-or-later
// What the service tests share: the receiving end of sd_notify, scene
// folders of their own, and a session made for a viewer.
#pragma once

#include "server_process.hpp"

#include <gio/gunixsocketaddress.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace caustic::testing {

using nlohmann::json;

// The receiving end of sd_notify: a Unix datagram socket.
class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path) : path_(path) {
    std::filesystem::remove(path_);
    socket_ = g_socket_new(G_SOCKET_FAMILY_UNIX, G_SOCKET_TYPE_DATAGRAM, G_SOCKET_PROTOCOL_DEFAULT, nullptr);
    GSocketAddress* address = g_unix_socket_address_new(path_.c_str());
    EXPECT_TRUE(g_socket_bind(socket_, address, TRUE, nullptr));
    g_object_unref(address);
  }
  ~NotifySocket() {
    g_object_unref(socket_);
    std::filesystem::remove(path_);
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
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::string matched_;
  GSocket* socket_ = nullptr;
};

// A scene folder with copies of built-in scenes whose mesh paths are absolute.
inline std::filesystem::path scene_folder(const std::string& name, std::initializer_list<const char*> scenes) {
  namespace fs = std::filesystem;
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

inline json create_session(const std::string& url, const std::string& scene) {
  const auto r = http("POST", url + "/api/v1/sessions", json{{"scene", scene}, {"codec", "vp8"}}.dump());
  EXPECT_EQ(r.status, 201u) << r.body;
  return r.json();
}

}  // namespace caustic::testing
