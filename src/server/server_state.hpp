// SPDX-License-Identifier: LGPL-2.1-or-later
// What the HTTP handlers share; lives on the main loop's thread.
#pragma once

#include "caustic/server/config.hpp"
#include "design_jobs.hpp"
#include "broadcast.hpp"
#include "gallery.hpp"
#include "instance.hpp"
#include "janus_admin.hpp"
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
  /// The API answers' Content-Security-Policy: made from `config` (Janus's
  /// WebSocket origin) whenever it is set, not for every request.
  std::string api_policy;
  std::filesystem::path data_dir;
  std::shared_ptr<const Gallery> gallery;
  std::string renderer;
  std::map<std::string, std::shared_ptr<Session>> sessions;
  Metrics metrics;
  SoupServer* soup = nullptr;
  std::unique_ptr<Listener> listener;
  RateLimiter rate_limiter;
  RateLimiter design_rate;                ///< uploads per address, apart from the other requests
  RateLimiter reconnect_rate;             ///< per session id: the stream rebuilt for a new socket
  RateLimiter receiver_rate;              ///< per session id: patches that set the receivers
  std::unique_ptr<DesignJobs> designs;    ///< null when the state folder is unusable
  bool draining = false;                  ///< stopping: no new sessions, running ones go on
  std::unique_ptr<CapacityAgent> agent;   ///< when agent_port is set
  std::unique_ptr<JanusAdmin> janus;      ///< when janus_admin_url is set: broadcasts
  std::map<std::string, Mountpoint> mountpoints;  ///< by session id, for broadcasts
  std::map<std::uint64_t, StrayMountpoint> strays;  ///< by mountpoint id: creates that got no answer
  std::map<std::uint64_t, Mountpoint> creating;     ///< by mountpoint id: creates not yet answered
  /// Broadcasts waiting for Janus to make their mountpoint, by address
  /// group: held already, so that requests made side by side are refused
  /// at once rather than each asking Janus for a mountpoint.
  std::map<std::string, int> starting;

  /// A scene for a session: the gallery's, else a finished design's; null
  /// if none, or (`*loading`) while the design is read back into memory.
  std::shared_ptr<const GalleryEntry> find_scene(const std::string& id, bool* loading) const;

  /// Removes a session on the next main loop iteration (never from inside
  /// one of its own callbacks).
  void end_session(const std::string& id, const std::string& reason);
  /// How many sessions `address` holds (max_sessions_per_address),
  /// broadcasts still starting included.
  int sessions_held_by(const std::string& address) const;
  /// Sessions running and broadcasts starting (max_sessions).
  int sessions_taken() const;
  /// Takes a token from `limiter`'s bucket `key` (`rate` a second, up to
  /// `burst`); when none is left, answers 429 with Retry-After and
  /// "`why`; retry after N s" (naming `problem_key` when given), counts it
  /// as rate-limited and returns false.
  bool within(RateLimiter& limiter, SoupServerMessage* msg, const std::string& key, double rate, double burst,
              const std::string& why, const std::string& problem_key = "");
};

/// Answers /api/v1/designs and /api/v1/designs/{id} (design_api.cpp);
/// false when `path` is neither.
bool route_designs(ServerState& s, SoupServerMessage* msg, const std::string& path);
/// GET /api/v1/sessions/{id}/frame.png or .exr (`hdr`), answered later (frame_api.cpp).
void session_frame(ServerState& s, SoupServerMessage* msg, Session& session, bool hdr);
/// POST /api/v1/sessions/{id}/drops (water_api.cpp).
void post_drop(ServerState& s, SoupServerMessage* msg, Session& session);
/// Parses a JSON object body of one of `types`, answering 415/413/400
/// itself on failure (session_create.cpp).
bool read_json_body(ServerState& s, SoupServerMessage* msg, std::initializer_list<const char*> types,
                    nlohmann::json* out);
/// Answers POST /api/v1/sessions (session_create.cpp).
void create_session(ServerState& s, SoupServerMessage* msg);
/// What a session's holder may see of its parameters: the scene without the
/// mesh, the version, fidelity, and warnings (`extra`: about what the
/// request itself wrote).
nlohmann::json public_params(Session& session, nlohmann::json extra = nlohmann::json::array());
/// 405 with the Allow header.
void not_allowed(ServerState& s, SoupServerMessage* msg, const char* allow);

/// Routes one HTTP request (registered on "/").
void handle_http(SoupServer*, SoupServerMessage* msg, const char* path, GHashTable* query, gpointer state);
/// Accepts a signalling WebSocket on /api/v1/sessions/{id}/signal?token=T.
void handle_signal_socket(SoupServer*, SoupServerMessage* msg, const char* path, SoupWebsocketConnection* socket,
                          gpointer state);
/// Sets the headers every answer carries (connected to "request-started").
void on_request_started(SoupServer*, SoupServerMessage* msg, gpointer state);
/// Drops the request's Range before any handler answers (connected to
/// "request-read"): byte ranges are not served.
void on_request_read(SoupServer*, SoupServerMessage* msg, gpointer state);
/// What the accept path enforces, from the configuration.
ListenerLimits listener_limits(const ServerConfig& config);

}  // namespace caustic::server
