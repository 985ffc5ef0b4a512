// SPDX-License-Identifier: LGPL-2.1-or-later
// The streaming plugin of the Janus WebRTC server, through Janus's admin
// API on this host: causticd creates a private mountpoint per broadcast
// session and destroys it with the session. Requests are asynchronous on
// the main loop (a Janus that hangs never blocks the server); each gets an
// answer or an error within `timeout_s`.
#pragma once

#include <libsoup/soup.h>
#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace caustic::server {

class JanusAdmin {
 public:
  /// `url`: the admin endpoint (http://127.0.0.1:7088/admin).
  JanusAdmin(std::string url, std::string admin_secret, std::string streaming_key, int timeout_s = 5);
  ~JanusAdmin();
  JanusAdmin(const JanusAdmin&) = delete;
  JanusAdmin& operator=(const JanusAdmin&) = delete;

  /// The plugin's answer ("response"), or `error` set: Janus unreachable,
  /// or the plugin's own error ("error_code" 455: no such mountpoint).
  struct Answer {
    nlohmann::json response;
    std::string error;
    int error_code = 0;
    /// Sent, but no answer came (a timeout, a connection lost): Janus may
    /// still carry the request out, a frozen one when it wakes.
    bool unanswered = false;
  };
  using Done = std::function<void(const Answer&)>;

  /// Sends `request` (a streaming plugin request: create, info, destroy...)
  /// with the admin credentials added. `done` runs on the main loop.
  void plugin_request(nlohmann::json request, Done done);

  /// Sends them all at once and waits for every answer (each within
  /// `timeout_s`, side by side): for the last requests while the server
  /// stops, when no main loop runs any more. Answers in request order.
  std::vector<Answer> plugin_requests_now(std::vector<nlohmann::json> requests, int timeout_s = 2);

  /// Janus's reply body read as an Answer; never throws: a body that is not
  /// a JSON object, or fields of other types, give an error instead.
  static Answer parse_answer(std::string_view body);

 private:
  SoupMessage* message(nlohmann::json request);  // null for a bad URL
  static Answer read_answer(SoupMessage* msg, GBytes* reply, GError* error);

  std::string url_, secret_, key_;
  SoupSession* http_ = nullptr;
  // Answers that arrive while (or after) this is destroyed are dropped:
  // their callbacks may reach into what owns it.
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  unsigned long long transaction_ = 0;
};

}  // namespace caustic::server
