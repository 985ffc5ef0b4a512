// SPDX-License-Identifier: LGPL-2.1-or-later
// Which requests may become a signalling socket (only those the accept path
// let go of as WebSockets, whose frames its guard follows), and how a socket
// that breaks the protocol is closed. Black-box over loopback.
#include "hardening_support.hpp"
#include "ws_client.hpp"

using namespace caustic::testing;

// The accept path follows a socket's frames (message size over its
// fragments, frame rate) only when the head it read was a GET without a
// body to a path ending in /signal as written. A handshake with a body, or
// with "/signal" escaped, was upgraded all the same: a socket none of those
// limits held, which the body timeout then cut off mid-session. Each is
// refused, leaves the session as it was, and a plain handshake still opens.
TEST(Hardening, OnlyAConnectionTheGuardFollowsBecomesASignallingSocket) {
  ServerProcess server;
  const json s = create_session(server);
  const std::string path = signal_path(s);
  const std::string fields = kWsUpgrade + ws_key_field() + kWsVersion;
  std::string escaped = path;
  escaped.replace(escaped.find("/signal"), 7, "/signa%6C");
  for (const std::string& request :
       {request_text("GET", path, fields, "hello"), request_text("GET", escaped, fields)}) {
    const int fd = raw_connect(server.port());
    ASSERT_GE(fd, 0);
    raw_send(fd, request);
    expect_problem_then_close(fd, 400);
    EXPECT_EQ(sessions_now(server), 1) << request;
  }
  const int fd = ws_open(server.port(), path);
  EXPECT_GE(fd, 0) << "a plain handshake after the refused ones";
  if (fd >= 0) ::close(fd);
}

// A frame that breaks RFC 6455 (a reserved bit set) or a text that is not
// UTF-8 made the library close the socket with a bare 1002 or 1007 and no
// `bye`: the page could not tell why. Each is said, in `bye` and in the close
// frame's reason, and the session ends with its socket.
TEST(Hardening, ASocketThatBreaksTheProtocolIsToldWhy) {
  ServerProcess server;
  struct Case {
    std::string frame;
    unsigned code;
    std::string reason;
  };
  std::string reserved = ws_frame_bytes(1, true, R"({"type": "ping"})", reinterpret_cast<const unsigned char*>("abcd"));
  reserved[0] = static_cast<char>(reserved[0] | 0x40);  // RSV1, with no extension that defines it
  const Case cases[] = {
      {reserved, 1002, "a frame that breaks the WebSocket protocol (RFC 6455)"},
      {ws_frame_bytes(1, true, "\xff\xfe", reinterpret_cast<const unsigned char*>("abcd")), 1007,
       "a text message that is not UTF-8"}};
  for (const Case& c : cases) {
    const int fd = ws_open(server.port(), signal_path(create_session(server)));
    ASSERT_GE(fd, 0);
    raw_send(fd, c.frame);
    const WsGoodbye goodbye = ws_goodbye(raw_read_all(fd, 10000));
    ::close(fd);
    EXPECT_EQ(goodbye.code, c.code);
    EXPECT_EQ(goodbye.reason.rfind(c.reason, 0), 0u) << goodbye.reason;
    EXPECT_EQ(goodbye.bye, goodbye.reason);
    EXPECT_TRUE(wait_sessions(server, 0, 20));
  }
}
