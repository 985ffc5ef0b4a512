// SPDX-License-Identifier: LGPL-2.1-or-later
// Regression tests for what an outsider could do to `causticd serve`: each
// one failed against the server before its fix. Black-box over loopback.
#include "hardening_support.hpp"
#include "ws_client.hpp"

#include <cmath>
#include <thread>

using caustic::testing::http;
using caustic::testing::Response;
using caustic::testing::ServerProcess;
using namespace caustic::testing;
using nlohmann::json;

TEST(Hardening, KeepAliveClientsThatCloseLeaveNoDescriptorBehind) {
  ServerProcess server;
  const std::string before_health = http("GET", server.url() + "/api/v1/health").body;
  const int baseline = open_descriptors(server.pid());
  for (int i = 0; i < 200; ++i) {
    // What curl and browsers do: keep-alive, read the answer, close.
    const int fd = raw_connect(server.port());
    ASSERT_GE(fd, 0);
    raw_send(fd, request_text("GET", "/api/v1/health", "Connection: keep-alive\r\n"));
    const std::string answer = raw_read_all(fd, 5000);
    EXPECT_EQ(raw_status(answer), 200);
    EXPECT_EQ(raw_header(answer, "Connection"), "close");
    ::close(fd);
  }
  int now = 0;
  for (int i = 0; i < 50 && (now = open_descriptors(server.pid())) > baseline + 2; ++i) g_usleep(100000);
  EXPECT_LE(now, baseline + 2) << "descriptors: " << baseline << " before, " << now << " after 200 requests";
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").body, before_health);
}

TEST(Hardening, MethodBytesThatAreNotUtf8Get400AndTheServerLives) {
  ServerProcess server;
  const std::vector<std::string> methods = {"\xff\xfe", "GE\xe9T", "G\x01T", std::string(40, 'A')};
  for (const std::string& method : methods) {
    for (const std::string path : {"/", "/api/v1/health", "/api/v1/sessions"}) {
      const std::string answer = raw_request(server.port(), method, path);
      expect_problem_answer(answer, 400);
      EXPECT_EQ(answer.find(method), std::string::npos) << "the method was echoed";
    }
  }
  // An unknown but well-formed method is a 405 that does not repeat it.
  const std::string answer = raw_request(server.port(), "BREW", "/api/v1/health");
  expect_problem_answer(answer, 405);
  EXPECT_EQ(raw_header(answer, "Allow"), "GET, HEAD");
  EXPECT_EQ(raw_body(answer).find("BREW"), std::string::npos);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Hardening, DeeplyNestedJsonIsRefusedWithoutRecursion) {
  ServerProcess server({"--set", "max_body_bytes=1048576"});
  const json s = create_session(server);
  const json before = http("GET", params_url(server, s), "", "", bearer(s)).json();
  const std::string deep = "{\"post\":" + std::string(60000, '[') + std::string(60000, ']') + "}";
  const Response r = http("PATCH", params_url(server, s), deep, "application/merge-patch+json", bearer(s));
  EXPECT_EQ(r.status, 400u) << r.body.substr(0, 200);
  EXPECT_NE(r.body.find("nested deeper"), std::string::npos) << r.body.substr(0, 200);
  // Where: the 33rd bracket ('{' at byte 0, the 32nd '[' at byte 8 + 31).
  EXPECT_NE(r.body.find("(byte 39)"), std::string::npos) << r.body.substr(0, 200);
  EXPECT_EQ(http("GET", params_url(server, s), "", "", bearer(s)).json(), before);
}

TEST(Hardening, AnOversizedBodyIsRefusedBeforeItIsSent) {
  ServerProcess server;
  const int fd = raw_connect(server.port());
  ASSERT_GE(fd, 0);
  // Only the head: the answer must come without a byte of the body.
  raw_send(fd,
           request_text("POST", "/api/v1/sessions", "Content-Type: application/json\r\nContent-Length: 134217728\r\n"));
  expect_problem_then_close(fd, 413);
}

// A client that sends its body after the 413 (most do, without Expect:
// 100-continue) must be able to: a server that closes with the body still
// arriving answers it with a reset, which a client can see before the 413
// ("broken pipe" while sending). The server reads and drops it instead.
TEST(Hardening, AnUploadRefusedWith413MaySendItsBodyWithoutAReset) {
  ServerProcess server;
  const int fd = raw_connect(server.port());
  ASSERT_GE(fd, 0);
  const std::size_t length = std::size_t{1} << 20;
  ASSERT_TRUE(raw_send(fd, request_text("POST", "/api/v1/sessions",
                                        "Content-Type: application/json\r\nContent-Length: " + std::to_string(length) +
                                            "\r\n")));
  pollfd answered{fd, POLLIN, 0};
  ASSERT_EQ(::poll(&answered, 1, 10000), 1) << "no answer to the head";
  const std::string chunk(64 * 1024, 'x');
  std::size_t sent = 0;
  for (; sent < length; sent += chunk.size()) {
    if (!raw_send(fd, chunk)) break;
    g_usleep(2000);  // a reset, had the server closed, arrives between two chunks
  }
  EXPECT_EQ(sent, length) << "sending the body failed: " << g_strerror(errno);
  ::shutdown(fd, SHUT_WR);
  expect_problem_then_close(fd, 413);
}

TEST(Hardening, ChunkedAndAmbiguousBodyLengthsAreRefused) {
  ServerProcess server;
  const std::string post = "POST /api/v1/sessions HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n";
  const std::string body = R"({"scene":"lens"})";
  const std::string length = std::to_string(body.size());
  expect_problem_answer(raw_request(server.port(), post + "Transfer-Encoding: chunked\r\n\r\n10\r\n" + body + "\r\n0\r\n\r\n"),
                        411);
  expect_problem_answer(
      raw_request(server.port(), post + "Content-Length: " + length + "\r\nContent-Length: " + length + "\r\n\r\n" + body),
      400);
  expect_problem_answer(raw_request(server.port(), post + "Content-Length: +" + length + "\r\n\r\n" + body), 400);
  expect_problem_answer(raw_request(server.port(), post + "Content-Length: " + length + "\r\nTransfer-Encoding: chunked\r\n\r\n" + body),
                        400);
  EXPECT_EQ(sessions_now(server), 0);
}

TEST(Hardening, JsonFollowedByANulByteIsRefused) {
  ServerProcess server;
  const json s = create_session(server);
  const json before = http("GET", params_url(server, s), "", "", bearer(s)).json();
  const std::string body = std::string(R"({"object": {"ior": 1.7}})") + '\0' + "junk";
  const Response r = http("PATCH", params_url(server, s), body, "application/merge-patch+json", bearer(s));
  EXPECT_EQ(r.status, 400u) << r.body;
  EXPECT_NE(r.body.find("at line 1, column 25 (byte 24)"), std::string::npos) << r.body;  // where it broke
  EXPECT_EQ(http("GET", params_url(server, s), "", "", bearer(s)).json(), before);
}

TEST(Hardening, AFragmentedWebSocketMessageOverTheLimitClosesTheSocket) {
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  // 16 fragments of 32 KiB: each frame is small, the message is 512 KiB.
  bool sent_all = ws_send_frame(fd, 1, false, std::string(32768, 'x'));
  for (int i = 0; i < 15 && sent_all; ++i) sent_all = ws_send_frame(fd, 0, i == 14, std::string(32768, 'x'));
  bool closed = false;
  const std::string said = raw_read_all(fd, 10000, &closed);
  ::close(fd);
  EXPECT_TRUE(closed) << "the server kept reading the message";
  // Told why, not just cut off: `bye`, then a close of code 1009.
  const WsGoodbye goodbye = ws_goodbye(said);
  EXPECT_EQ(goodbye.code, 1009u);
  EXPECT_EQ(goodbye.reason, "a WebSocket message is larger than 65536 bytes");
  EXPECT_EQ(goodbye.bye, goodbye.reason);
  // A ping longer than a control frame may be: a protocol error, said so.
  const int ping = ws_open(server.port(), signal_path(create_session(server)));
  ASSERT_GE(ping, 0);
  ws_send_frame(ping, 9, true, std::string(126, 'x'));
  const WsGoodbye broken = ws_goodbye(raw_read_all(ping, 10000));
  ::close(ping);
  EXPECT_EQ(broken.code, 1002u);
  EXPECT_EQ(broken.reason, "a WebSocket control frame must be whole and at most 125 bytes");
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Hardening, IdleAndTricklingClientsAreClosedAfterTheHeadTimeout) {
  ServerProcess server({"--set", "header_timeout_s=1"});
  const int idle = raw_connect(server.port());
  const int loris = raw_connect(server.port());
  ASSERT_GE(idle, 0);
  ASSERT_GE(loris, 0);
  const std::string head = "GET /api/v1/health HTTP/1.1\r\nHost: x\r\n";
  bool loris_closed = false;
  std::string loris_answer;
  // One byte every 200 ms: never a whole head within the second allowed.
  for (std::size_t i = 0; i < head.size() && !loris_closed; ++i) {
    raw_send(loris, head.substr(i, 1));
    loris_answer += raw_read_all(loris, 200, &loris_closed);
  }
  bool idle_closed = false;
  const std::string idle_answer = raw_read_all(idle, 10000, &idle_closed);
  EXPECT_TRUE(loris_closed);
  EXPECT_TRUE(idle_closed);
  expect_problem_answer(idle_answer, 408);
  ::close(idle);
  ::close(loris);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Hardening, AnUpgradeThatBecomesNoSignallingSocketKeepsItsTimeouts) {
  // Any GET with "Upgrade: websocket" was let go of every timeout: one that
  // never sent the body it announced, or was answered and kept alive, held
  // its connection for good (64 an address). Bounded: four connections.
  ServerProcess server({"--set", "body_timeout_s=1", "--set", "connection_idle_timeout_s=1"});
  const std::string upgrade =
      "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
      "Sec-WebSocket-Version: 13\r\n";
  const int stalled = raw_connect(server.port());
  ASSERT_GE(stalled, 0);
  raw_send(stalled, request_text("GET", "/api/v1/health", upgrade + "Content-Length: 100\r\n"));
  bool closed = false;
  raw_read_all(stalled, 15000, &closed);
  EXPECT_TRUE(closed) << "a body announced and never sent held its connection";
  ::close(stalled);
  // Answered anywhere but as a signalling socket: closed after the answer.
  for (const char* path : {"/api/v1/health", "/x/signal", "/api/v1/sessions/00000000000000000000000000000000/signal"}) {
    const int fd = raw_connect(server.port());
    ASSERT_GE(fd, 0);
    raw_send(fd, request_text("GET", path, upgrade));
    closed = false;
    const std::string answer = raw_read_all(fd, 15000, &closed);
    EXPECT_TRUE(closed) << path << ": " << answer;
    EXPECT_NE(raw_status(answer), 101) << path;
    ::close(fd);
  }
}

TEST(Hardening, ConnectionsBeyondThePerAddressLimitGet503AtOnce) {
  ServerProcess server({"--set", "max_connections_per_address=4"});
  std::vector<int> held;
  for (int i = 0; i < 4; ++i) held.push_back(raw_connect(server.port()));
  g_usleep(200000);  // let the server accept them
  const std::string answer = raw_request(server.port(), request_text("GET", "/api/v1/health"), 5000);
  expect_problem_answer(answer, 503);
  EXPECT_FALSE(raw_header(answer, "Retry-After").empty());
  for (int fd : held) ::close(fd);
  // Once they are gone, the address is welcome again.
  int status = 0;
  for (int i = 0; i < 50 && status != 200; ++i, g_usleep(100000))
    status = raw_status(raw_request(server.port(), request_text("GET", "/api/v1/health"), 5000));
  EXPECT_EQ(status, 200);
}

TEST(Hardening, AcceptingResumesAfterDescriptorsRanOut) {
  // A process with few descriptors: idle clients use them all up.
  ServerProcess server({"--set", "max_connections=1000", "--set", "max_connections_per_address=1000"}, {},
                       CAUSTICD_BINARY, {"/usr/bin/prlimit", "--nofile=64:64"});
  std::vector<int> held;
  for (int i = 0; i < 120; ++i) {
    const int fd = raw_connect(server.port());
    if (fd >= 0) held.push_back(fd);
  }
  g_usleep(500000);
  for (int fd : held) ::close(fd);
  int status = 0;
  for (int i = 0; i < 100 && status != 200; ++i, g_usleep(100000))
    status = raw_status(raw_request(server.port(), request_text("GET", "/api/v1/health"), 2000));
  EXPECT_EQ(status, 200) << "the server stopped accepting for good";
  const std::string metrics = http("GET", server.url() + "/metrics").body;
  EXPECT_EQ(metrics.find("causticd_accept_failures_total 0\n"), std::string::npos) << "descriptors never ran out";
}

TEST(Hardening, MutatingRequestsBeyondTheRateGet429WithRetryAfter) {
  ServerProcess server({"--set", "rate_limit_per_s=1", "--set", "rate_limit_burst=4"});
  const json s = create_session(server);  // one token
  int ok = 0, limited = 0;
  std::string retry_after;
  for (int i = 0; i < 6; ++i) {
    const Response r = http("PATCH", params_url(server, s), R"({"post": {"exposure": 1.5}})",
                            "application/merge-patch+json", bearer(s));
    if (r.status == 200u) ++ok;
    if (r.status == 429u) {
      ++limited;
      EXPECT_EQ(r.content_type, "application/problem+json");
      EXPECT_EQ(json::parse(r.body)["title"], "Too Many Requests") << r.body;  // not libsoup's "Unknown Error"
    }
  }
  EXPECT_GE(ok, 3);
  EXPECT_GE(limited, 1);
  // Reads are never limited.
  EXPECT_EQ(http("GET", params_url(server, s), "", "", bearer(s)).status, 200u);
}

TEST(Hardening, ScreenBisectionFindsThePublicBoxNotTheSurface) {
  ServerProcess server;
  // The public proxy of the lens: its slab's bounding box.
  json proxy;
  const json listing = http("GET", server.url() + "/api/v1/scenes").json();
  for (const auto& scene : listing["scenes"])
    if (scene["id"] == "lens") proxy = scene["proxy"];
  ASSERT_TRUE(proxy.is_object());
  const json s = create_session(server);
  // A screen tilted 40 degrees about x: its plane meets the box at a corner,
  // where a spherical cap is much thinner than the box.
  const double a = 40.0 * M_PI / 180.0;
  const double n[3] = {0, std::sin(a), std::cos(a)}, up[3] = {0, std::cos(a), -std::sin(a)};
  auto place = [&](double z) {
    return http("PATCH", params_url(server, s),
                json{{"screen", {{"center", {0, 0, z}}, {"normal", {n[0], n[1], n[2]}}, {"up", {up[0], up[1], up[2]}}}}}
                    .dump(),
                "application/merge-patch+json", bearer(s));
  };
  ASSERT_EQ(place(-80).status, 200u) << place(-80).body;
  double lo = -80, hi = 0;  // lo: accepted, hi: refused
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (place(mid).status == 200u ? lo : hi) = mid;
  }
  // The boundary the proxy predicts: the plane through (0, 0, z) touches
  // the box's lowest corner along n.
  const double c[3] = {proxy["center"][0], proxy["center"][1], proxy["center"][2]};
  const double w = proxy["outline"][0], h = proxy["outline"][1], t = proxy["thickness"];
  double lowest = 1e300;
  for (int i = 0; i < 8; ++i) {
    const double p[3] = {c[0] + ((i & 1) ? 0.5 : -0.5) * w, c[1] + ((i & 2) ? 0.5 : -0.5) * h,
                         c[2] + ((i & 4) ? 0.5 : -0.5) * t};
    lowest = std::min(lowest, p[0] * n[0] + p[1] * n[1] + p[2] * n[2]);
  }
  EXPECT_NEAR(lo, lowest / n[2], 1e-6) << "the refusals follow something other than the public box";
}

TEST(Hardening, AnswersCarryAllowAndSecurityHeadersAndNoPackageFiles) {
  ServerProcess server;
  const std::string page = raw_request(server.port(), "GET", "/");
  EXPECT_EQ(raw_status(page), 200);
  EXPECT_NE(raw_header(page, "Content-Security-Policy").find("frame-ancestors 'none'"), std::string::npos);
  EXPECT_EQ(raw_header(page, "X-Frame-Options"), "DENY");
  EXPECT_EQ(raw_header(page, "Referrer-Policy"), "no-referrer");
  for (const char* file : {"/package.json", "/package-lock.json"})
    expect_problem_answer(raw_request(server.port(), "GET", file), 404);
  const std::string put = raw_request(server.port(), "PUT", "/api/v1/sessions", "Content-Length: 0\r\n");
  expect_problem_answer(put, 405);
  EXPECT_EQ(raw_header(put, "Allow"), "POST");
  // What the HTTP library would have answered with an empty 400 or 404.
  for (const char* line : {"GET / HTTP/3.0", "GET * HTTP/1.1", "CONNECT 127.0.0.1:80 HTTP/1.1", "GET /%00 HTTP/1.1",
                           "GET /%zz HTTP/1.1", "GET /% HTTP/1.1", "GET /..%2f..%2fetc%2fpasswd HTTP/1.1",
                           "GET /a|b HTTP/1.1"})
    expect_problem_answer(raw_request(server.port(), std::string(line) + "\r\nHost: x\r\n\r\n"), 400);
  expect_problem_answer(raw_request(server.port(), "GET / HTTP/1.1\r\nHost: x:y\r\n\r\n"), 400);
  const json s = create_session(server);
  expect_problem_answer(raw_request(server.port(), "GET", signal_path(s),
                                    "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: short\r\n"
                                    "Sec-WebSocket-Version: 13\r\n"),
                        400);
}

TEST(Hardening, ByteRangesAreNotServedAndOtherExpectationsGetAProblem) {
  ServerProcess server;
  for (const std::string path : {"/index.html", "/api/v1/scenes"}) {
    const std::string whole = raw_request(server.port(), "GET", path);
    ASSERT_EQ(raw_status(whole), 200) << path;
    EXPECT_EQ(raw_header(whole, "Accept-Ranges"), "none");
    // The HTTP library answered 200 ranges with as many copies, built in
    // memory; a suffix longer than the file with a broken 206 (and GLib
    // criticals); a start beyond it with an empty text/html 416.
    std::string many = "bytes=0-";
    for (int i = 0; i < 200; ++i) many += ",0-";
    for (const std::string& range : {many, std::string("bytes=-100000"), std::string("bytes=999999999-"),
                                     std::string("bytes=0-1")}) {
      const std::string answer = raw_request(server.port(), "GET", path, "Range: " + range + "\r\n");
      EXPECT_EQ(raw_status(answer), 200) << path << " " << range.substr(0, 20);
      EXPECT_EQ(raw_body(answer).size(), raw_body(whole).size()) << path << " " << range.substr(0, 20);
    }
  }
  // Any expectation but 100-continue: the library's 417 had no body.
  expect_problem_answer(raw_request(server.port(), "GET", "/index.html", "Expect: foo\r\n"), 417);
  const std::string continued = raw_request(server.port(), "POST", "/api/v1/sessions",
                                            "Expect: 100-Continue\r\nContent-Type: application/json\r\n",
                                            R"({"scene": "slab"})");
  EXPECT_NE(continued.find(" 201 "), std::string::npos) << continued.substr(0, 200);
}

TEST(Hardening, ABinarySignallingMessageGetsAnError) {
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  ws_send_frame(fd, 2, true, std::string("\x01\x02\x03", 3));
  bool errored = false;
  for (int i = 0; i < 10 && !errored; ++i) {
    const auto message = ws_read_text(fd, 10000);
    if (!message) break;
    errored = json::parse(*message, nullptr, false).value("type", "") == "error";
  }
  EXPECT_TRUE(errored);
  ::close(fd);
}

TEST(Hardening, AHeadCutShortByTheClientIsAnsweredAtOnce) {
  // Far longer than the test waits: only the client's half-close can end it.
  ServerProcess server({"--set", "header_timeout_s=600"});
  const int fd = raw_connect(server.port());
  ASSERT_GE(fd, 0);
  raw_send(fd, "GET /api/v1/health HTTP/1.1\r\nHost: x\r\n");
  ::shutdown(fd, SHUT_WR);
  expect_problem_then_close(fd, 400, 30000);
}

TEST(Hardening, ANullHigherUpCannotResetTheFixedKeys) {
  ServerProcess server;
  const json s = create_session(server);
  const json before = http("GET", params_url(server, s), "", "", bearer(s)).json();
  // The lens's flat face sits at an offset its scene sets. A null restores
  // the scene's own value (docs/api.md), never the computed default, so a
  // fixed key keeps its value whatever null a patch holds.
  ASSERT_EQ(before["params"]["object"]["flat_face_offset"], 4.0);
  for (const char* patch : {R"({"object": null})", R"({"object": {"flat_face_offset": null}})"}) {
    const Response r = http("PATCH", params_url(server, s), patch, "application/merge-patch+json", bearer(s));
    EXPECT_EQ(r.status, 200u) << patch << ": " << r.body;
    EXPECT_EQ(r.json()["params"], before["params"]) << patch;
  }
  const Response moved = http("PATCH", params_url(server, s), R"({"object": {"flat_face_offset": 3}})",
                              "application/merge-patch+json", bearer(s));
  EXPECT_EQ(moved.status, 422u) << moved.body;
  EXPECT_EQ(http("GET", params_url(server, s), "", "", bearer(s)).json()["params"], before["params"]);
}
