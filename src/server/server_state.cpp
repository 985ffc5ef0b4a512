// SPDX-License-Identifier: LGPL-2.1-or-later
// What the server's parts share (server_state.hpp): the sessions an address
// holds, a session's end, and the answer of a limit.
#include "address_group.hpp"
#include "broadcast.hpp"
#include "http_util.hpp"
#include "instance.hpp"
#include "log.hpp"
#include "server_state.hpp"

#include <malloc.h>

namespace caustic::server {

int ServerState::sessions_held_by(const std::string& address) const {
  // Counted by address group: one IPv6 client may take any address of its /64.
  const std::string group = address_group(address);
  int held = 0;
  for (const auto& [id, session] : sessions) held += address_group(session->client_address()) == group;
  const auto it = starting.find(group);
  return held + (it == starting.end() ? 0 : it->second);
}

int ServerState::sessions_taken() const {
  int taken = static_cast<int>(sessions.size());
  for (const auto& [group, count] : starting) taken += count;
  return taken;
}

void ServerState::end_session(const std::string& id, const std::string& reason) {
  auto it = sessions.find(id);
  if (it == sessions.end()) return;
  // Keep the session alive until the main loop is back at the top: this may
  // run inside one of its own callbacks.
  auto* doomed = new std::shared_ptr<Session>(it->second);
  sessions.erase(it);
  log(Level::info, "session " + id + " ended: " + reason, (*doomed)->log_context());
  (*doomed)->close(reason);
  end_broadcast(*this, id);
  // Once it is gone, the heap it held goes back to the system: a session's
  // frames and copies are tens of megabytes, kept by glibc's arenas (as the
  // server's peak) until a trim, whichever way the session ended.
  g_idle_add_full(
      G_PRIORITY_DEFAULT_IDLE, [](gpointer) -> gboolean { return G_SOURCE_REMOVE; }, doomed,
      [](gpointer data) {
        delete static_cast<std::shared_ptr<Session>*>(data);
        malloc_trim(0);
      });
}

bool ServerState::within(RateLimiter& limiter, SoupServerMessage* msg, const std::string& key, double rate,
                         double burst, const std::string& why, const std::string& problem_key) {
  int retry = 1;
  if (limiter.admit(key, rate, burst, &retry)) return true;
  ++metrics.rate_limited;
  soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After",
                               std::to_string(retry).c_str());
  reply_problem(msg, metrics, 429, why + "; retry after " + std::to_string(retry) + " s", problem_key);
  return false;
}

ListenerLimits listener_limits(const ServerConfig& c) {
  ListenerLimits l;
  l.max_connections = c.max_connections;
  l.max_connections_per_address = c.max_connections_per_address;
  l.header_timeout_s = c.header_timeout_s;
  l.body_timeout_s = c.body_timeout_s;
  l.connection_idle_timeout_s = c.connection_idle_timeout_s;
  l.max_ws_message_bytes = c.max_ws_message_bytes;
  l.trusted_proxies = c.trusted_proxies;
  l.head.max_body_bytes = c.max_body_bytes;
  // An instance's prefix is its path's too (instance.hpp): the same route.
  l.head.upload_paths = {"/api/v1/designs"};
  if (!url_prefix(c).empty()) l.head.upload_paths.push_back(url_prefix(c) + "/api/v1/designs");
  l.head.max_upload_bytes = static_cast<std::size_t>(c.design_max_upload_bytes);
  return l;
}

}  // namespace caustic::server
