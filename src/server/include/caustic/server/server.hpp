// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd serve`: the HTTP API, WebSocket signalling, static web files and
// one streaming pipeline per session, on the calling thread's GLib main loop.
#pragma once

#include "caustic/server/config.hpp"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace caustic::server {

/// Sends GLib's and the libraries' own messages (g_warning() and the like)
/// through the server's log (journald fields under systemd, the levels of
/// log_level) instead of raw to stderr. Call once, before gst_init().
void route_library_messages();

class Server {
 public:
  /// Loads the gallery and prepares the HTTP server. Throws std::runtime_error.
  Server(ServerConfig config, std::filesystem::path data_dir);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Starts listening; returns the URL (with the real port when port is 0).
  std::string listen();
  /// Runs the main loop until quit(): SIGINT and SIGTERM call it too, after
  /// telling systemd STOPPING=1; the destructor then closes every session.
  /// Sends READY=1 (sd_notify) when the loop starts, WATCHDOG=1 while every
  /// session's streaming thread keeps producing frames, and reloads on SIGHUP.
  void run();

  /// What SIGHUP re-reads: the configuration (file, environment, flags).
  /// Without one, SIGHUP reloads only the gallery.
  void set_config_reloader(std::function<ServerConfig()> reload);

  /// Re-reads the configuration at once and the gallery on a thread of its
  /// own (requests are answered meanwhile from the old one), without
  /// touching running sessions (they keep their scene); a bad configuration
  /// or an empty gallery is logged and the old one kept. READY=1 follows
  /// once the new gallery is in. Main loop thread only.
  void reload();
  void quit();

 private:
  void start_gallery_reload();
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace caustic::server
