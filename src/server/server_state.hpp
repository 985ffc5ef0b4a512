// What the HTTP handlers share; lives on the main loop's thread.
#pragma once

#include "caustic/server/config.hpp"
#include "gallery.hpp"
#include "metrics.hpp"
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

  /// Removes a session on the next main loop iteration (never from inside
  /// one of its own callbacks).
  void end_session(const std::string& id, const std::string& reason);
};

/// Routes one HTTP request (registered on "/").
void handle_http(SoupServer*, SoupServerMessage* msg, const char* path, GHashTable* query, gpointer state);
/// Accepts a signalling WebSocket on /api/v1/sessions/{id}/signal?token=T.
void handle_signal_socket(SoupServer*, SoupServerMessage* msg, const char* path, SoupWebsocketConnection* socket,
                          gpointer state);
/// Refuses request bodies larger than the configured limit before they are read.
void handle_early(SoupServer*, SoupServerMessage* msg, const char* path, GHashTable* query, gpointer state);

}  // namespace caustic::server
