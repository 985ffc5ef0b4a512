// SPDX-License-Identifier: LGPL-2.1-or-later
#include "listener.hpp"

#include "address_group.hpp"
#include "guard_stream.hpp"
#include "log.hpp"
#include "peer.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>

namespace caustic::server {

struct Listener::Connection {
  std::uint64_t id = 0;
  GSocket* socket = nullptr;  // owned until handed over, then watched weakly
  std::string address;
  std::string group;  // address_group(address): what max_connections_per_address counts
  guint16 port = 0;  // the client's, which with the address names the connection
  bool handed = false;
  bool websocket = false;  // handed over as a WebSocket (RequestHead::websocket)
  std::uint64_t upload = 0;  // the length of its body when larger than max_body_bytes: a picture
  std::size_t peeked = 0;
  GSource* io = nullptr;
  guint timer = 0;     // head deadline, re-check, drain limit or answer deadline
  guint recheck = 0;
  GWeakRef stream{};   // the library's once handed over: a late request is answered 408 on it
  ~Connection() { g_weak_ref_clear(&stream); }
};

namespace {

struct Gone {
  std::weak_ptr<Listener*> owner;
  std::uint64_t id;
};

void clear_source(GSource*& source) {
  if (!source) return;
  g_source_destroy(source);
  g_source_unref(source);
  source = nullptr;
}

void clear_timer(guint& id) {
  if (id) g_source_remove(id);
  id = 0;
}

// A main-loop callback that finds its listener and connection by id, so a
// callback that fires after either is gone does nothing.
template <typename Fn>
guint after_ms(std::weak_ptr<Listener*> owner, guint ms, Fn fn) {
  auto* job = new std::pair<std::weak_ptr<Listener*>, Fn>(std::move(owner), std::move(fn));
  return g_timeout_add_full(
      G_PRIORITY_DEFAULT, ms,
      [](gpointer data) -> gboolean {
        auto* j = static_cast<std::pair<std::weak_ptr<Listener*>, Fn>*>(data);
        if (auto l = j->first.lock()) j->second(**l);
        return G_SOURCE_REMOVE;
      },
      job, [](gpointer data) { delete static_cast<std::pair<std::weak_ptr<Listener*>, Fn>*>(data); });
}

}  // namespace

Listener::Listener(SoupServer* server, Metrics& metrics, ListenerLimits limits)
    : server_(server), metrics_(metrics), limits_(limits), alive_(std::make_shared<Listener*>(this)) {
  // The guard holds a socket's messages to max_ws_message_bytes on the wire;
  // permessage-deflate would inflate them past it unchecked (libsoup 3.2 made
  // 50 MB of 48 KB), and signalling messages are a few KiB.
  soup_server_remove_websocket_extension(server_, SOUP_TYPE_WEBSOCKET_EXTENSION_DEFLATE);
}

Listener::~Listener() {
  alive_.reset();
  clear_source(accept_source_);
  clear_timer(retry_);
  for (auto& [id, c] : connections_) {
    clear_source(c->io);
    clear_timer(c->timer);
    clear_timer(c->recheck);
    if (!c->handed && c->socket) g_object_unref(c->socket);
  }
  if (socket_) {
    g_socket_close(socket_, nullptr);
    g_object_unref(socket_);
  }
}

bool port_trouble(const GError* error) {
  return error && (g_error_matches(error, G_IO_ERROR, G_IO_ERROR_ADDRESS_IN_USE) ||
                   g_error_matches(error, G_IO_ERROR, G_IO_ERROR_PERMISSION_DENIED));
}

std::string Listener::listen(const std::string& address, int port) {
  GInetAddress* inet = g_inet_address_new_from_string(address == "localhost" ? "127.0.0.1" : address.c_str());
  if (!inet) throw ListenError("cannot use bind address " + address, false);
  GSocketAddress* where = g_inet_socket_address_new(inet, static_cast<guint16>(port));
  GError* error = nullptr;
  socket_ = g_socket_new(g_inet_address_get_family(inet), G_SOCKET_TYPE_STREAM, G_SOCKET_PROTOCOL_TCP, &error);
  g_object_unref(inet);
  auto fail = [&](const std::string& what) {
    const std::string message = what + ": " + (error ? error->message : "unknown error");
    const bool port = port_trouble(error);
    if (error) g_error_free(error);
    g_object_unref(where);
    throw ListenError(message, port);
  };
  if (!socket_) fail("cannot make a socket");
  g_socket_set_blocking(socket_, FALSE);
  g_socket_set_listen_backlog(socket_, 1024);
  if (!g_socket_bind(socket_, where, TRUE, &error)) fail("cannot listen on " + address + ":" + std::to_string(port));
  if (!g_socket_listen(socket_, &error)) fail("cannot listen on " + address + ":" + std::to_string(port));
  g_object_unref(where);
  GSocketAddress* bound = g_socket_get_local_address(socket_, nullptr);
  const int real_port = bound ? g_inet_socket_address_get_port(G_INET_SOCKET_ADDRESS(bound)) : port;
  if (bound) g_object_unref(bound);
  arm_accept();
  const bool v6 = address.find(':') != std::string::npos;
  return "http://" + (v6 ? "[" + address + "]" : address) + ":" + std::to_string(real_port) + "/";
}

void Listener::arm_accept() {
  clear_source(accept_source_);
  accept_source_ = g_socket_create_source(socket_, G_IO_IN, nullptr);
  auto* owner = new std::weak_ptr<Listener*>(alive_);
  g_source_set_callback(
      accept_source_,
      G_SOURCE_FUNC(+[](GSocket*, GIOCondition, gpointer data) -> gboolean {
        if (auto l = static_cast<std::weak_ptr<Listener*>*>(data)->lock()) (*l)->accept_some();
        return G_SOURCE_CONTINUE;
      }),
      owner, [](gpointer data) { delete static_cast<std::weak_ptr<Listener*>*>(data); });
  g_source_attach(accept_source_, nullptr);
}

bool Listener::accepting(std::chrono::seconds grace) const {
  if (!socket_) return false;
  if (!failing_since_) return true;
  return std::chrono::steady_clock::now() - *failing_since_ < grace;
}

void Listener::accept_some() {
  // A bounded batch per wake-up keeps the main loop responsive in a flood.
  for (int i = 0; i < 64; ++i) {
    GError* error = nullptr;
    GSocket* client = g_socket_accept(socket_, nullptr, &error);
    if (client) {
      failing_since_.reset();
      admit(client);
      continue;
    }
    const bool would_block = g_error_matches(error, G_IO_ERROR, G_IO_ERROR_WOULD_BLOCK);
    const bool exhausted = g_error_matches(error, G_IO_ERROR, G_IO_ERROR_TOO_MANY_OPEN_FILES) ||
                           (error && error->domain == G_IO_ERROR && (errno == EMFILE || errno == ENFILE));
    g_error_free(error);
    if (would_block) return;
    if (exhausted) {
      // The pending connection stays in the backlog; stop polling a socket
      // that stays readable, and try again shortly.
      if (!failing_since_) {
        failing_since_ = std::chrono::steady_clock::now();
        log(Level::error, "out of file descriptors: accepting again when some are free");
      }
      ++metrics_.accept_failures;
      clear_source(accept_source_);
      clear_timer(retry_);
      retry_ = after_ms(alive_, 250, [](Listener& l) {
        l.retry_ = 0;
        l.arm_accept();
      });
      return;
    }
    // ECONNABORTED and the like concern one client only.
  }
}

void Listener::refuse(GSocket* socket, unsigned status, const std::string& detail, const std::string& headers,
                      bool linger) {
  ++metrics_.http_errors;
  ++metrics_.connections_refused;
  const std::string answer = canned_problem(status, detail, headers);
  const int fd = g_socket_get_fd(socket);
  (void)::send(fd, answer.data(), answer.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  ::shutdown(fd, SHUT_WR);
  if (linger && lingering_.take(fd)) return;
  // Read what the client already sent, so closing sends a FIN after the
  // answer rather than a reset that could destroy it in flight.
  char sink[4096];
  for (int i = 0; i < 16 && ::recv(fd, sink, sizeof sink, MSG_DONTWAIT) > 0; ++i) {
  }
}

void Listener::admit(GSocket* socket) {
  const Peer peer = peer_of(socket);
  const std::string address = address_group(peer.address);  // what the limit counts
  const int total = static_cast<int>(connections_.size());
  const int from_here = per_address_[address];
  if (total >= limits_.max_connections || from_here >= limits_.max_connections_per_address) {
    refuse(socket, 503,
           total >= limits_.max_connections ? "the server has too many connections" : "too many connections from your address",
           "Retry-After: 1\r\n");
    g_socket_close(socket, nullptr);
    g_object_unref(socket);
    if (from_here == 0) per_address_.erase(address);
    return;
  }
  ++per_address_[address];
  ++metrics_.connections_accepted;
  auto c = std::make_unique<Connection>();
  c->id = next_id_++;
  c->socket = socket;
  c->address = peer.address;
  c->group = address;
  c->port = peer.port;
  const std::uint64_t id = c->id;
  c->timer = after_ms(alive_, static_cast<guint>(limits_.header_timeout_s * 1000), [id](Listener& l) {
    auto it = l.connections_.find(id);
    if (it == l.connections_.end() || it->second->handed) return;
    it->second->timer = 0;
    ++l.metrics_.connections_timed_out;
    l.refuse(it->second->socket, 408, "the request head did not arrive in time");
    l.drop(id);
  });
  connections_[id] = std::move(c);
  peek(id);
}

void Listener::peek(std::uint64_t id) {
  auto it = connections_.find(id);
  if (it == connections_.end()) return;
  Connection& c = *it->second;
  clear_source(c.io);
  std::string buffer(limits_.head.max_head_bytes, '\0');
  const ssize_t n = ::recv(g_socket_get_fd(c.socket), buffer.data(), buffer.size(), MSG_PEEK | MSG_DONTWAIT);
  if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) return drop(id);
  const bool nothing_new = n < 0 || static_cast<std::size_t>(n) == c.peeked;
  if (!nothing_new) {
    c.peeked = static_cast<std::size_t>(n);
    buffer.resize(static_cast<std::size_t>(n));
    const RequestHead head = scan_request_head(buffer, limits_.head);
    if (head.state == RequestHead::State::complete) {
      if (const char* why = upload_refusal(c, head)) {
        refuse(c.socket, 503, why, "Retry-After: 2\r\n", true);
        return drop(id);
      }
      return hand_over(id, head);
    }
    if (head.state == RequestHead::State::refused) {
      refuse(c.socket, head.status, head.detail, "", head.status == 413);
      return drop(id);
    }
  }
  // A client that stopped sending (shut its side) with the head unfinished
  // will never finish it: answer now rather than at the head timeout.
  pollfd hangup{g_socket_get_fd(c.socket), POLLRDHUP, 0};
  if (n > 0 && ::poll(&hangup, 1, 0) == 1 && (hangup.revents & (POLLRDHUP | POLLHUP))) {
    refuse(c.socket, 400, "the request head ended before its blank line");
    return drop(id);
  }
  // The peeked bytes keep the socket readable: wait a little before looking
  // again instead of spinning (a client sends a head in one packet; only a
  // trickling one pays this).
  clear_timer(c.recheck);
  c.recheck = after_ms(alive_, nothing_new ? 50 : 10, [id](Listener& l) {
    auto it = l.connections_.find(id);
    if (it == l.connections_.end()) return;
    Connection& c = *it->second;
    c.recheck = 0;
    c.io = g_socket_create_source(c.socket, GIOCondition(G_IO_IN | G_IO_HUP | G_IO_ERR), nullptr);
    auto* gone = new Gone{l.alive_, id};
    g_source_set_callback(
        c.io,
        G_SOURCE_FUNC(+[](GSocket*, GIOCondition, gpointer data) -> gboolean {
          auto* g = static_cast<Gone*>(data);
          if (auto l = g->owner.lock()) (*l)->peek(g->id);
          return G_SOURCE_REMOVE;
        }),
        gone, [](gpointer data) { delete static_cast<Gone*>(data); });
    g_source_attach(c.io, nullptr);
  });
}

const char* Listener::upload_refusal(const Connection& c, const RequestHead& head) const {
  // The library holds a body whole until its handler runs: 40 clients sending
  // 8 MiB pictures but their last bytes held 324 MB for the body timeout.
  if (head.content_length <= limits_.head.max_body_bytes) return nullptr;
  std::uint64_t all = 0, here = 0;
  for (const auto& [id, other] : connections_) {
    all += other->upload;
    if (other->group == c.group) here += other->upload;
  }
  const std::uint64_t largest = limits_.head.max_upload_bytes;
  const auto& trusted = limits_.trusted_proxies;  // many visitors share a proxy's address
  if (std::find(trusted.begin(), trusted.end(), c.address) == trusted.end() && here + head.content_length > largest)
    return "a picture from your address is still arriving";
  if (all + head.content_length > kUploadsAtOnce * largest) return "too many pictures are arriving at once";
  return nullptr;
}

void Listener::hand_over(std::uint64_t id, const RequestHead& head) {
  Connection& c = *connections_.at(id);
  if (head.content_length > limits_.head.max_body_bytes) c.upload = head.content_length;
  clear_source(c.io);
  clear_timer(c.timer);
  clear_timer(c.recheck);
  c.handed = true;
  c.websocket = head.websocket;
  GSocket* socket = c.socket;
  if (!head.websocket) g_socket_set_timeout(socket, static_cast<guint>(limits_.connection_idle_timeout_s));
  // The library writes an answer's head and body apart; without this the
  // body waits for the client's delayed ACK (40 ms) on every answer.
  g_socket_set_option(socket, IPPROTO_TCP, TCP_NODELAY, TRUE, nullptr);
  GSocketConnection* connection = g_socket_connection_factory_create_connection(socket);
  GIOStream* stream = guarded_stream_new(connection, head.websocket ? head.head_bytes : 0, limits_.max_ws_message_bytes,
                                         head.head_bytes + head.content_length, head.ignored_expects, &metrics_.http_errors);
  g_weak_ref_set(&c.stream, stream);
  GSocketAddress* local = g_socket_get_local_address(socket, nullptr);
  GSocketAddress* remote = g_socket_get_remote_address(socket, nullptr);
  // From here the stream owns the socket; the record only watches it.
  g_object_weak_ref(G_OBJECT(socket), socket_gone, new Gone{alive_, id});
  g_object_unref(socket);
  if (local && remote) soup_server_accept_iostream(server_, stream, local, remote, nullptr);
  else g_io_stream_close(stream, nullptr, nullptr);
  if (local) g_object_unref(local);
  if (remote) g_object_unref(remote);
  g_object_unref(stream);
  g_object_unref(connection);
  if (head.websocket) return;  // the session watches its viewer from here
  auto it = connections_.find(id);
  if (it == connections_.end()) return;
  it->second->timer = after_ms(alive_, static_cast<guint>(limits_.body_timeout_s * 1000), [id](Listener& l) {
    auto it = l.connections_.find(id);
    if (it == l.connections_.end()) return;
    it->second->timer = 0;
    ++l.metrics_.connections_timed_out;
    // A request still arriving is told why (408); then shutting the socket
    // down makes the library's next read or write fail, and it lets go.
    if (GIOStream* stream = static_cast<GIOStream*>(g_weak_ref_get(&it->second->stream))) {
      guarded_stream_time_out(stream, "body_timeout_s");  // counted by the stream
      g_object_unref(stream);
    }
    if (it->second->socket) g_socket_shutdown(it->second->socket, TRUE, TRUE, nullptr);
  });
}

void Listener::drop(std::uint64_t id) {
  auto it = connections_.find(id);
  if (it == connections_.end()) return;
  Connection& c = *it->second;
  clear_source(c.io);
  clear_timer(c.timer);
  clear_timer(c.recheck);
  if (!c.handed) {
    g_socket_close(c.socket, nullptr);
    g_object_unref(c.socket);
  }
  if (--per_address_[c.group] <= 0) per_address_.erase(c.group);
  connections_.erase(it);
}

const Listener::Connection* Listener::connection_of(SoupServerMessage* msg) const {
  GSocketAddress* remote = soup_server_message_get_remote_address(msg);
  if (!remote || !G_IS_INET_SOCKET_ADDRESS(remote)) return nullptr;
  const Peer peer = peer_of(remote);
  for (const auto& [id, c] : connections_)
    if (c->port == peer.port && c->address == peer.address && c->socket) return c.get();
  return nullptr;  // its record is gone with its socket
}

bool Listener::client_connected(SoupServerMessage* msg) const {
  const Connection* c = connection_of(msg);
  if (!c) return false;
  pollfd hangup{g_socket_get_fd(c->socket), POLLRDHUP, 0};
  return !(::poll(&hangup, 1, 0) == 1 && (hangup.revents & (POLLRDHUP | POLLHUP | POLLERR)));
}

bool Listener::guards_websocket(SoupServerMessage* msg) const {
  const Connection* c = connection_of(msg);
  return c && c->websocket;
}

void Listener::socket_gone(gpointer data, GObject*) {
  std::unique_ptr<Gone> gone(static_cast<Gone*>(data));
  auto l = gone->owner.lock();
  if (!l) return;
  Listener& self = **l;
  auto it = self.connections_.find(gone->id);
  if (it == self.connections_.end()) return;
  it->second->socket = nullptr;  // handed over: drop() forgets the record, closes nothing
  self.drop(gone->id);
}

}  // namespace caustic::server
