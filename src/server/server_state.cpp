// SPDX-License-Identifier: LGPL-2.1-or-later
// What the server's parts share (server_state.hpp): the sessions an address
// holds, and a session's end.
#include "address_group.hpp"
#include "broadcast.hpp"
#include "log.hpp"
#include "server_state.hpp"

#include <malloc.h>

namespace caustic::server {

int ServerState::sessions_held_by(const std::string& address) const {
  // Counted by address group: one IPv6 client may take any address of its /64.
  const std::string group = address_group(address);
  int held = 0;
  for (const auto& [id, session] : sessions) held += address_group(session->client_address()) == group;
  return held;
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

}  // namespace caustic::server
