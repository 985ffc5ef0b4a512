// SPDX-License-Identifier: LGPL-2.1-or-later
// The server's own accept path in front of the HTTP library. The library's
// listener gives up for good after one failed accept (descriptor
// exhaustion), has a backlog of 10, no limit on connections and no timeout
// on a client that trickles its request; this one accepts with a large
// backlog, counts connections in total and per client address (503 beyond),
// reads and checks each request head itself before the library sees it
// (request_head.hpp), closes clients that are too slow, backs off and
// recovers when descriptors run out, and hands every admitted connection to
// the library through a guarded stream (guard_stream.hpp).
#pragma once

#include "lingering_close.hpp"
#include "metrics.hpp"
#include "request_head.hpp"

#include <libsoup/soup.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustic::server {

/// Pictures of the largest size (design_max_upload_bytes) that may arrive
/// at once: the design queue's default length.
inline constexpr std::uint64_t kUploadsAtOnce = 4;

struct ListenerLimits {
  int max_connections = 512;
  int max_connections_per_address = 64;
  int header_timeout_s = 10;           ///< the request head must arrive within this
  int body_timeout_s = 30;             ///< head to answer sent, plain HTTP
  int connection_idle_timeout_s = 10;  ///< no byte moving for this long, plain HTTP
  std::uint64_t max_ws_message_bytes = 64 * 1024;
  std::vector<std::string> trusted_proxies;  ///< many visitors' pictures come from each
  HeadLimits head;
};

/// A socket that could not be bound. `port`: the port stands in the way
/// (taken, or below 1024 without the right to it); otherwise the address
/// (not this host's, or not up yet). A restart may mend either, the port
/// freed or the address up: the caller names the setting, and the process
/// exits 1, which systemd retries, rather than 2.
struct ListenError : std::runtime_error {
  ListenError(const std::string& what, bool port) : std::runtime_error(what), port(port) {}
  bool port;
};

/// Whether a failed bind's `error` is the port's (ListenError::port).
bool port_trouble(const GError* error);

class Listener {
 public:
  Listener(SoupServer* server, Metrics& metrics, ListenerLimits limits);
  ~Listener();
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;

  /// Binds and listens (backlog 1024); returns the URL with the real port.
  /// Throws ListenError.
  std::string listen(const std::string& address, int port);
  /// Limits for connections accepted from now on.
  void set_limits(const ListenerLimits& limits) { limits_ = limits; }
  /// False while accepting has failed (no descriptors left) for over `grace`.
  bool accepting(std::chrono::seconds grace = std::chrono::seconds(5)) const;
  int open_connections() const { return static_cast<int>(connections_.size()); }
  /// False once the client of `msg`'s connection has closed it (or its
  /// sending side): the library does not watch the connection of a request
  /// it was told to pause, so an answer that waits on another server asks
  /// here before acting for a client that may have left.
  bool client_connected(SoupServerMessage* msg) const;
  /// Whether `msg`'s connection was handed over as a WebSocket, its frames
  /// followed by the guard (guard_stream.hpp) and free of the HTTP
  /// timeouts: the head check's word (RequestHead::websocket), which only
  /// such a connection may be upgraded on.
  bool guards_websocket(SoupServerMessage* msg) const;

 private:
  struct Connection;
  // The record of `msg`'s connection while its socket is open, or null.
  const Connection* connection_of(SoupServerMessage* msg) const;
  void arm_accept();
  void accept_some();
  void admit(GSocket* socket);
  void peek(std::uint64_t id);
  // `linger`: the client may still be sending a body (LingeringClose).
  void refuse(GSocket* socket, unsigned status, const std::string& detail, const std::string& headers = "",
              bool linger = false);
  // Why a body larger than max_body_bytes (a picture) may not come now:
  // one the size of the largest picture at a time from an address, and
  // kUploadsAtOnce of them in all. Null when it may.
  const char* upload_refusal(const Connection& c, const RequestHead& head) const;
  void hand_over(std::uint64_t id, const RequestHead& head);
  void drop(std::uint64_t id);
  static void socket_gone(gpointer data, GObject* where);

  SoupServer* server_;
  Metrics& metrics_;
  ListenerLimits limits_;
  GSocket* socket_ = nullptr;
  GSource* accept_source_ = nullptr;
  guint retry_ = 0;
  std::optional<std::chrono::steady_clock::time_point> failing_since_;
  std::map<std::uint64_t, std::unique_ptr<Connection>> connections_;
  std::map<std::string, int> per_address_;
  std::uint64_t next_id_ = 1;
  // Refused uploads: 32 at once, each for at most 1 s and 4 MiB.
  LingeringClose lingering_{32, std::chrono::milliseconds(1000), std::size_t{4} << 20};
  std::shared_ptr<Listener*> alive_;  // callbacks hold a weak copy
};

}  // namespace caustic::server
