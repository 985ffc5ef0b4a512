// SPDX-License-Identifier: LGPL-2.1-or-later
// The stream the HTTP library reads a connection through. It holds the
// socket connection and closes it when the library closes the stream (so a
// descriptor never outlives its connection), and on a WebSocket connection
// it follows the client's frames past the request head with a
// WebSocketGuard, failing the read that would exceed the message limit.
#pragma once

#include <gio/gio.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace caustic::server {

/// The domain of the errors a guarded WebSocket's read fails with: the code
/// is the WebSocket close code they call for (1009 a message too large, 1002
/// a broken control frame, 1008 more frames than a signalling socket takes),
/// the message says why in at most 123 bytes, as a close frame's reason.
GQuark guard_error_quark();

/// A new stream for the HTTP library over `connection` (a reference is
/// taken). `websocket_after`: 0 for plain HTTP; otherwise the byte count of
/// the request head, after which frames are checked. `request_bytes`, for
/// plain HTTP: the head's and the body's length together. `ignored_expects`:
/// where Expect field names the library must not see start in the head
/// (RequestHead::ignored_expects); each reaches it as "Ignore". `errors`:
/// counts each answer the stream sends itself (408, 400 below), as
/// Metrics::http_errors counts the library's; it outlives the stream.
GIOStream* guarded_stream_new(GSocketConnection* connection, std::size_t websocket_after,
                              std::uint64_t max_message_bytes, std::uint64_t request_bytes = 0,
                              const std::vector<std::size_t>& ignored_expects = {},
                              std::atomic<std::uint64_t>* errors = nullptr);

/// On a plain HTTP stream of guarded_stream_new() whose request has not all
/// arrived, answers 408 (a problem naming `timeout`) straight on the socket
/// and returns true; false otherwise. The library answers only once it has
/// read the request, so nothing of its own comes before; a client that
/// stalls mid-body is told why it is cut off, not just cut off. A read the
/// socket's idle timeout ends does the same by itself (a 408 naming
/// connection_idle_timeout_s), and so does a body the client ends early
/// (a 400).
bool guarded_stream_time_out(GIOStream* stream, const char* timeout);

}  // namespace caustic::server
