// SPDX-License-Identifier: LGPL-2.1-or-later
// A client's address as text ("unknown" without one) and its port: with
// both, one connection among several from the same host. What the accept
// path records of a socket, and what finds its record again from a
// request the library hands over.
#pragma once

#include <gio/gio.h>

#include <string>

namespace caustic::server {

struct Peer {
  std::string address = "unknown";
  guint16 port = 0;
};

inline Peer peer_of(GSocketAddress* remote) {
  Peer peer;
  if (!remote || !G_IS_INET_SOCKET_ADDRESS(remote)) return peer;
  gchar* s = g_inet_address_to_string(g_inet_socket_address_get_address(G_INET_SOCKET_ADDRESS(remote)));
  peer.address = s;
  g_free(s);
  peer.port = g_inet_socket_address_get_port(G_INET_SOCKET_ADDRESS(remote));
  return peer;
}

inline Peer peer_of(GSocket* socket) {
  GSocketAddress* remote = g_socket_get_remote_address(socket, nullptr);
  const Peer peer = peer_of(remote);
  if (remote) g_object_unref(remote);
  return peer;
}

}  // namespace caustic::server
