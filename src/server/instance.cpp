// SPDX-License-Identifier: LGPL-2.1-or-later
#include "instance.hpp"

#include "server_state.hpp"

#include <cmath>

namespace caustic::server {

std::string url_prefix(const ServerConfig& config) {
  return config.instance_index > 0 ? "/i/" + std::to_string(config.instance_index) : "";
}

PathOwner strip_instance_prefix(const ServerConfig& config, std::string& path) {
  if (path.rfind("/i/", 0) != 0) return PathOwner::this_instance;
  const std::string own = url_prefix(config);
  // "/i/<n>" alone is this instance's too: it names nothing here (404), not
  // another instance (421).
  if (!own.empty() && (path == own || path.rfind(own + "/", 0) == 0)) {
    path.erase(0, own.size());
    return PathOwner::this_instance;
  }
  return PathOwner::other_instance;
}

int free_sessions(const ServerState& s) {
  if (s.draining) return 0;
  return std::max(0, s.config.max_sessions - s.sessions_taken());  // broadcasts waiting for Janus included
}

std::string agent_answer(const ServerState& s) {
  if (s.draining) return "up drain\n";
  // A weight relative to the one in the proxy's configuration: an instance
  // with more room free gets more of the new sessions, a full one none.
  const int percent = static_cast<int>(std::lround(100.0 * free_sessions(s) / s.config.max_sessions));
  return "up ready " + std::to_string(percent) + "%\n";
}

CapacityAgent::CapacityAgent(const ServerState& state, const std::string& address, int port) {
  service_ = g_socket_service_new();
  GInetAddress* inet = g_inet_address_new_from_string(address == "localhost" ? "127.0.0.1" : address.c_str());
  GSocketAddress* where = inet ? g_inet_socket_address_new(inet, static_cast<guint16>(port)) : nullptr;
  GError* error = nullptr;
  const bool bound =
      where && g_socket_listener_add_address(G_SOCKET_LISTENER(service_), where, G_SOCKET_TYPE_STREAM,
                                             G_SOCKET_PROTOCOL_TCP, nullptr, nullptr, &error);
  if (where) g_object_unref(where);
  if (inet) g_object_unref(inet);
  if (!bound) {
    const std::string why = error ? error->message : "not an address";
    const bool port_taken = port_trouble(error);
    if (error) g_error_free(error);
    g_object_unref(service_);
    throw ListenError("cannot listen on " + address + ":" + std::to_string(port) + ": " + why, port_taken);
  }
  g_signal_connect(service_, "incoming",
                   G_CALLBACK(+[](GSocketService*, GSocketConnection* connection, GObject*, gpointer data) -> gboolean {
                     const std::string line = agent_answer(*static_cast<const ServerState*>(data));
                     // A few bytes into a fresh socket's empty send buffer: this does not block.
                     GOutputStream* out = g_io_stream_get_output_stream(G_IO_STREAM(connection));
                     g_output_stream_write_all(out, line.data(), line.size(), nullptr, nullptr, nullptr);
                     g_io_stream_close(G_IO_STREAM(connection), nullptr, nullptr);
                     return TRUE;
                   }),
                   const_cast<ServerState*>(&state));
  g_socket_service_start(service_);
}

CapacityAgent::~CapacityAgent() {
  g_socket_service_stop(service_);
  g_socket_listener_close(G_SOCKET_LISTENER(service_));
  g_object_unref(service_);
}

}  // namespace caustic::server
