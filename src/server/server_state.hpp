// What the HTTP handlers share; lives on the main loop's thread.
#pragma once

#include "caustic/server/config.hpp"
#include "gallery.hpp"
#include "listener.hpp"
#include "metrics.hpp"
#include "rate_limit.hpp"
#include "session.hpp"

#include <libsoup/soup.h>

#include <map>
#include <memory>
#include <string>

namespace caustic::server {

struct ServerState {
  ServerConfig config;
  std::filesystem::path data_dir;
  std::shared_ptr<const Gallery> gallery;
  std::string renderer;
  std::map<std::string, std::shared_ptr<Session>> sessions;
  Metrics metrics;
  SoupServer* soup = nullptr;
  std::unique_ptr<Listener> listener;
  RateLimiter rate_limiter;

  /// Removes a session on the next main loop iteration (never from inside
  /// one of its own callbacks).
  void end_session(const std::string& id, const std::string& reason);
};

/// Routes one HTTP request (registered on "/").
void handle_http(SoupServer*, SoupServerMessage* msg, const char* path, GHashTable* query, gpointer state);
/// Accepts a signalling WebSocket on /api/v1/sessions/{id}/signal?token=T.
void handle_signal_socket(SoupServer*, SoupServerMessage* msg, const char* path, SoupWebsocketConnection* socket,
                          gpointer state);
/// Sets the headers every answer carries (connected to "request-started").
void on_request_started(SoupServer*, SoupServerMessage* msg, gpointer state);
/// What the accept path enforces, from the configuration.
ListenerLimits listener_limits(const ServerConfig& config);

}  // namespace caustic::server
