// `causticd serve`: the HTTP API, WebSocket signalling, static web files and
// one streaming pipeline per session, on the calling thread's GLib main loop.
#pragma once

#include "caustic/server/config.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace caustic::server {

class Server {
 public:
  /// Loads the gallery and prepares the HTTP server. Throws std::runtime_error.
  Server(ServerConfig config, std::filesystem::path data_dir);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Starts listening; returns the URL (with the real port when port is 0).
  std::string listen();
  /// Runs the main loop until quit() (SIGINT and SIGTERM call it too).
  void run();
  void quit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace caustic::server
