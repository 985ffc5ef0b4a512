// SPDX-License-Identifier: LGPL-2.1-or-later
// A WebSocket client for tests that keeps every text message it receives,
// driven on the thread-default main context: it connects (waiting up to
// 5 s), then spin() runs the context until a condition holds or time is up.
#pragma once

#include <glib.h>
#include <libsoup/soup.h>

#include <functional>
#include <string>
#include <vector>

namespace caustic::testing {

class WebSocketListener {
 public:
  /// `protocol`: the subprotocol asked for (Janus's "janus-protocol"), or none.
  explicit WebSocketListener(const std::string& url, const char* protocol = nullptr) {
    SoupMessage* msg = soup_message_new("GET", url.c_str());
    const char* protocols[] = {protocol, nullptr};
    soup_session_websocket_connect_async(
        http_, msg, nullptr, protocol ? const_cast<char**>(protocols) : nullptr, G_PRIORITY_DEFAULT, nullptr,
        [](GObject* source, GAsyncResult* result, gpointer data) {
          auto* self = static_cast<WebSocketListener*>(data);
          self->socket = soup_session_websocket_connect_finish(SOUP_SESSION(source), result, nullptr);
          if (!self->socket) return;
          g_signal_connect(self->socket, "message", G_CALLBACK(+[](SoupWebsocketConnection*, gint, GBytes* bytes, gpointer me) {
                             gsize size = 0;
                             const auto* text = static_cast<const char*>(g_bytes_get_data(bytes, &size));
                             static_cast<WebSocketListener*>(me)->messages.emplace_back(text, size);
                           }),
                           self);
        },
        this);
    g_object_unref(msg);
    spin([&] { return socket != nullptr; }, 5000);
  }
  ~WebSocketListener() {
    if (socket) g_object_unref(socket);
    g_object_unref(http_);
  }
  WebSocketListener(const WebSocketListener&) = delete;
  WebSocketListener& operator=(const WebSocketListener&) = delete;

  /// Runs the main context until `done` or `ms` pass; whether `done`.
  bool spin(const std::function<bool()>& done, int ms) {
    for (int waited = 0; waited < ms && !done(); waited += 5) {
      while (g_main_context_iteration(nullptr, FALSE)) {
      }
      g_usleep(5000);
    }
    return done();
  }
  /// Whether a message received so far holds `what`.
  bool heard(const std::string& what) const {
    for (const auto& m : messages)
      if (m.find(what) != std::string::npos) return true;
    return false;
  }

  SoupWebsocketConnection* socket = nullptr;  ///< null when the connection failed
  std::vector<std::string> messages;          ///< every text message, in order

 private:
  SoupSession* http_ = soup_session_new();
};

}  // namespace caustic::testing
