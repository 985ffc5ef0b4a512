// SPDX-License-Identifier: LGPL-2.1-or-later
// The stream the HTTP library reads a connection through. It holds the
// socket connection and closes it when the library closes the stream (so a
// descriptor never outlives its connection), and on a WebSocket connection
// it follows the client's frames past the request head with a
// WebSocketGuard, failing the read that would exceed the message limit.
#pragma once

#include <gio/gio.h>

#include <cstddef>
#include <cstdint>

namespace caustic::server {

/// A new stream for the HTTP library over `connection` (a reference is
/// taken). `websocket_after`: 0 for plain HTTP; otherwise the byte count of
/// the request head, after which frames are checked.
GIOStream* guarded_stream_new(GSocketConnection* connection, std::size_t websocket_after,
                              std::uint64_t max_message_bytes);

}  // namespace caustic::server
