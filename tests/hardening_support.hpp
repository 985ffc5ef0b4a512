// SPDX-License-Identifier: LGPL-2.1-or-later
// What the hardening tests share: sessions on a ServerProcess, bearer
// headers, problem+json checks on raw answers, how a WebSocket was closed
// and polling the session count.
#pragma once

#include "raw_http.hpp"
#include "server_process.hpp"

#include <glib.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace caustic::testing {

using nlohmann::json;

inline json create_session(const ServerProcess& server, const std::string& scene = "lens") {
  const Response r = http("POST", server.url() + "/api/v1/sessions", json{{"scene", scene}}.dump());
  EXPECT_EQ(r.status, 201u) << r.body;
  return r.json();
}

inline std::string params_url(const ServerProcess& server, const json& s) {
  return server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/params";
}

inline std::string signal_path(const json& s) { return s["signal_url"].get<std::string>(); }

inline void expect_problem_answer(const std::string& answer, int status) {
  EXPECT_EQ(raw_status(answer), status) << answer.substr(0, 300);
  EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json") << answer.substr(0, 300);
  // Refused early (before libsoup reads the request) or late, the same safety headers.
  EXPECT_EQ(raw_header(answer, "X-Content-Type-Options"), "nosniff") << answer.substr(0, 300);
  EXPECT_EQ(raw_header(answer, "X-Frame-Options"), "DENY") << answer.substr(0, 300);
  EXPECT_FALSE(raw_header(answer, "Content-Security-Policy").empty()) << answer.substr(0, 300);
  const json body = json::parse(raw_body(answer), nullptr, false);
  ASSERT_TRUE(body.is_object()) << answer.substr(0, 300);
  EXPECT_EQ(body["status"], status);
  EXPECT_TRUE(body["detail"].is_string());
}

/// Reads what the server sends on `fd` until it closes (at most
/// `timeout_ms`), closes `fd`, and expects a problem answer of `status`
/// followed by the server's close.
inline void expect_problem_then_close(int fd, int status, int timeout_ms = 10000) {
  bool closed = false;
  const std::string answer = raw_read_all(fd, timeout_ms, &closed);
  ::close(fd);
  expect_problem_answer(answer, status);
  EXPECT_TRUE(closed) << "the server kept the connection open";
}

/// How a server's WebSocket frames (unmasked, as read after the handshake)
/// end: the close frame's code (0 when none came) and reason, and the reason
/// of a `bye` message before it.
struct WsGoodbye {
  unsigned code = 0;
  std::string reason, bye;
};
inline WsGoodbye ws_goodbye(const std::string& bytes) {
  WsGoodbye out;
  for (std::size_t at = 0; at + 2 <= bytes.size();) {
    const auto byte = [&](std::size_t i) { return static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[i])); };
    const unsigned opcode = byte(at) & 0x0f, n = byte(at + 1) & 0x7f;
    const std::size_t header = n == 126 ? 4 : n == 127 ? 10 : 2;
    std::uint64_t length = n;
    if (header > 2) length = 0;
    for (std::size_t i = 2; i < header && at + i < bytes.size(); ++i) length = (length << 8) | byte(at + i);
    if (at + header + length > bytes.size()) break;
    const std::string payload = bytes.substr(at + header, length);
    if (opcode == 1) {
      const json message = json::parse(payload, nullptr, false);
      if (message.is_object() && message.value("type", "") == "bye") out.bye = message.value("reason", "");
    }
    if (opcode == 8 && payload.size() >= 2) {
      out.code = static_cast<unsigned>(byte(at + header) << 8 | byte(at + header + 1));
      out.reason = payload.substr(2);
      break;
    }
    at += header + length;
  }
  return out;
}

inline int sessions_now(const ServerProcess& server) {
  return http("GET", server.url() + "/api/v1/health").json()["sessions"].get<int>();
}

/// Polls until the server holds `want` sessions or `seconds` pass.
inline bool wait_sessions(const ServerProcess& server, int want, double seconds) {
  for (int i = 0; i < seconds * 10; ++i) {
    if (sessions_now(server) == want) return true;
    g_usleep(100000);
  }
  return sessions_now(server) == want;
}

}  // namespace caustic::testing
