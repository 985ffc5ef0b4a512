// SPDX-License-Identifier: LGPL-2.1-or-later
// Which requests may become a signalling socket: only those the accept path
// let go of as WebSockets, whose frames its guard follows. Black-box over
// loopback.
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
