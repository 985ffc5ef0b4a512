// SPDX-License-Identifier: LGPL-2.1-or-later
#include "guard_stream.hpp"

#include "request_head.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <string_view>

namespace caustic::server {
namespace {

// Frames a signalling socket may send: a burst (an answer and its
// candidates), then a steady rate (a ping every few seconds). libsoup reads
// a socket until it would block, so a client that never stopped sending
// kept the main loop for itself: health took 14 s to answer during 15 s of
// pings, and ping frames, each answered into a queue the client did not
// read, slowed it further.
constexpr double kFrameBurst = 256, kFramesPerS = 20;

struct GuardInput {
  GFilterInputStream parent;
  GSocketConnection* connection;
  std::size_t skip;                          // head bytes still to pass unchecked
  std::unique_ptr<WebSocketGuard>* frames;   // null: plain HTTP
  double frame_tokens;                       // what the socket may still send (kFrameBurst)
  std::uint64_t frames_paid;                 // frames taken from them so far
  std::chrono::steady_clock::time_point refilled;
  std::uint64_t request_bytes;               // plain HTTP: head and body
  std::uint64_t read_bytes;                  // what the library read so far
  bool timed_out;                            // a 408 was sent
  std::vector<std::size_t>* ignored_expects;  // plain HTTP: field names to hide
  std::atomic<std::uint64_t>* errors;        // counts the answers sent here (http_errors)
};
struct GuardInputClass {
  GFilterInputStreamClass parent_class;
};

GType guard_input_get_type();
void guard_input_pollable_init(GPollableInputStreamInterface* iface);

G_DEFINE_TYPE_WITH_CODE(GuardInput, guard_input, G_TYPE_FILTER_INPUT_STREAM,
                        G_IMPLEMENT_INTERFACE(G_TYPE_POLLABLE_INPUT_STREAM, guard_input_pollable_init))

GuardInput* self_of(gpointer p) { return reinterpret_cast<GuardInput*>(p); }
GInputStream* base_of(gpointer p) { return g_filter_input_stream_get_base_stream(G_FILTER_INPUT_STREAM(p)); }

// A problem on the socket, once, while the request is still arriving: the
// library answers only once it has read the request, and closes without a
// word when the request never comes whole.
bool cut_off(GuardInput* self, unsigned status, const std::string& detail) {
  if (self->frames || self->timed_out || self->read_bytes >= self->request_bytes || !self->connection) return false;
  self->timed_out = true;
  const std::string answer = canned_problem(status, detail);
  GSocket* socket = g_socket_connection_get_socket(self->connection);
  (void)::send(g_socket_get_fd(socket), answer.data(), answer.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  // Counted here, whichever timeout or cut sent it: the library never
  // sees this answer, so the count of its answers misses it.
  if (self->errors) ++*self->errors;
  return true;
}

bool time_out(GuardInput* self, const char* timeout) {
  return cut_off(self, 408, std::string("the request did not arrive in time (") + timeout + "); it was cut off");
}

// Rewrites each Expect field name the library must not see, where this
// read holds it, as "Ignore" (as long, so no length changes).
void hide_expects(GuardInput* self, void* buffer, std::size_t n) {
  static constexpr std::string_view kName = "Ignore";
  auto* bytes = static_cast<char*>(buffer);
  for (const std::size_t at : *self->ignored_expects)
    for (std::size_t i = 0; i < kName.size(); ++i)
      if (at + i >= self->read_bytes && at + i < self->read_bytes + n) bytes[at + i - self->read_bytes] = kName[i];
}

// Checks what a read returned before the library sees it.
gssize inspect(GuardInput* self, void* buffer, gssize n, GError** error) {
  if (!self->frames) {
    if (n > 0 && !self->ignored_expects->empty()) hide_expects(self, buffer, static_cast<std::size_t>(n));
    if (n > 0) self->read_bytes += static_cast<std::uint64_t>(n);
    else if (n < 0 && error && *error && g_error_matches(*error, G_IO_ERROR, G_IO_ERROR_TIMED_OUT))
      time_out(self, "connection_idle_timeout_s");
    // The client closed its sending side with the body unfinished; it may
    // still read, as after a head cut short (listener.cpp).
    else if (n == 0)
      cut_off(self, 400, "the body ended before its Content-Length did: the client closed its side");
    return n;
  }
  if (n <= 0) return n;
  const auto* bytes = static_cast<const unsigned char*>(buffer);
  std::size_t from = 0;
  if (self->skip) {
    from = std::min<std::size_t>(self->skip, static_cast<std::size_t>(n));
    self->skip -= from;
  }
  WebSocketGuard& guard = **self->frames;
  if (!guard.feed(bytes + from, static_cast<std::size_t>(n) - from)) {
    g_set_error_literal(error, guard_error_quark(), static_cast<gint>(guard.close_code()), guard.error().c_str());
    return -1;
  }
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - self->refilled).count();
  self->frame_tokens = std::min(kFrameBurst, self->frame_tokens + elapsed * kFramesPerS);
  self->refilled = now;
  self->frame_tokens -= static_cast<double>(guard.frames() - self->frames_paid);
  self->frames_paid = guard.frames();
  if (self->frame_tokens < 0) {
    g_set_error_literal(error, guard_error_quark(), 1008, "more WebSocket frames than a signalling socket takes");
    return -1;
  }
  return n;
}

gssize guard_read(GInputStream* stream, void* buffer, gsize count, GCancellable* cancellable, GError** error) {
  const gssize n = g_input_stream_read(base_of(stream), buffer, count, cancellable, error);
  return inspect(self_of(stream), buffer, n, error);
}

gboolean guard_close(GInputStream* stream, GCancellable* cancellable, GError** error) {
  GuardInput* self = self_of(stream);
  gboolean ok = G_INPUT_STREAM_CLASS(guard_input_parent_class)->close_fn(stream, cancellable, error);
  // The library closes the stream it was given; closing the connection here
  // closes the descriptor even where the library keeps a reference.
  if (self->connection) g_io_stream_close(G_IO_STREAM(self->connection), nullptr, nullptr);
  return ok;
}

gboolean guard_can_poll(GPollableInputStream* stream) {
  return G_IS_POLLABLE_INPUT_STREAM(base_of(stream)) &&
         g_pollable_input_stream_can_poll(G_POLLABLE_INPUT_STREAM(base_of(stream)));
}

gboolean guard_is_readable(GPollableInputStream* stream) {
  return g_pollable_input_stream_is_readable(G_POLLABLE_INPUT_STREAM(base_of(stream)));
}

GSource* guard_create_source(GPollableInputStream* stream, GCancellable* cancellable) {
  GSource* base = g_pollable_input_stream_create_source(G_POLLABLE_INPUT_STREAM(base_of(stream)), cancellable);
  GSource* source = g_pollable_source_new_full(stream, base, cancellable);
  g_source_unref(base);
  return source;
}

gssize guard_read_nonblocking(GPollableInputStream* stream, void* buffer, gsize count, GError** error) {
  const gssize n =
      g_pollable_input_stream_read_nonblocking(G_POLLABLE_INPUT_STREAM(base_of(stream)), buffer, count, nullptr, error);
  return inspect(self_of(stream), buffer, n, error);
}

void guard_input_pollable_init(GPollableInputStreamInterface* iface) {
  iface->can_poll = guard_can_poll;
  iface->is_readable = guard_is_readable;
  iface->create_source = guard_create_source;
  iface->read_nonblocking = guard_read_nonblocking;
}

void guard_finalize(GObject* object) {
  GuardInput* self = self_of(object);
  delete self->frames;
  delete self->ignored_expects;
  g_clear_object(&self->connection);
  G_OBJECT_CLASS(guard_input_parent_class)->finalize(object);
}

void guard_input_class_init(GuardInputClass* klass) {
  G_OBJECT_CLASS(klass)->finalize = guard_finalize;
  G_INPUT_STREAM_CLASS(klass)->read_fn = guard_read;
  G_INPUT_STREAM_CLASS(klass)->close_fn = guard_close;
}

void guard_input_init(GuardInput* self) {
  self->connection = nullptr;
  self->skip = 0;
  self->frames = nullptr;
  self->frame_tokens = kFrameBurst;
  self->frames_paid = 0;
  self->refilled = std::chrono::steady_clock::now();
  self->request_bytes = self->read_bytes = 0;
  self->timed_out = false;
  self->ignored_expects = nullptr;
  self->errors = nullptr;
}

}  // namespace

GQuark guard_error_quark() { return g_quark_from_static_string("causticd-websocket-guard"); }

GIOStream* guarded_stream_new(GSocketConnection* connection, std::size_t websocket_after,
                              std::uint64_t max_message_bytes, std::uint64_t request_bytes,
                              const std::vector<std::size_t>& ignored_expects, std::atomic<std::uint64_t>* errors) {
  GIOStream* io = G_IO_STREAM(connection);
  auto* input = self_of(g_object_new(guard_input_get_type(), "base-stream", g_io_stream_get_input_stream(io),
                                     "close-base-stream", TRUE, nullptr));
  input->connection = G_SOCKET_CONNECTION(g_object_ref(connection));
  input->request_bytes = request_bytes;
  input->ignored_expects = new std::vector<std::size_t>(ignored_expects);
  input->errors = errors;
  if (websocket_after) {
    input->skip = websocket_after;
    // Frames are at most the message limit too: one frame is one message.
    input->frames = new std::unique_ptr<WebSocketGuard>(
        std::make_unique<WebSocketGuard>(max_message_bytes, max_message_bytes));
  }
  GIOStream* stream = g_simple_io_stream_new(G_INPUT_STREAM(input), g_io_stream_get_output_stream(io));
  g_object_unref(input);
  return stream;
}

bool guarded_stream_time_out(GIOStream* stream, const char* timeout) {
  GInputStream* input = g_io_stream_get_input_stream(stream);
  return G_TYPE_CHECK_INSTANCE_TYPE(input, guard_input_get_type()) && time_out(self_of(input), timeout);
}

}  // namespace caustic::server
