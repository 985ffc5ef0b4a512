// SPDX-License-Identifier: LGPL-2.1-or-later
// Hardening of bodies on their way in: the HTTP library holds a body whole
// in memory until its handler runs, so the pictures arriving at once are
// bounded; a body that stops coming is answered 408 before the close, one
// the client cut short 400.
// Black-box over loopback, from several of its addresses.
#include "hardening_support.hpp"
#include "raw_http.hpp"

using namespace caustic::testing;

namespace {

constexpr std::size_t kLargest = 1 << 20;  // design_max_upload_bytes below

// Starts a picture of `length` bytes and sends `sent` of them.
int start_upload(int port, int host, std::size_t length, std::size_t sent) {
  // From 127.0.0.`host` (all of 127/8 is loopback): each host its own share.
  const int fd = raw_connect(port, "127.0.0." + std::to_string(host));
  if (fd < 0) return fd;
  raw_send(fd, request_text("POST", "/api/v1/designs",
                            "Content-Type: image/png\r\nContent-Length: " + std::to_string(length) + "\r\n") +
                   std::string(sent, 'p'));
  return fd;
}

// The answer to an upload of the largest size from 127.0.0.`host`, asked
// again (each a new connection, given 2 s) until it is `status` or 20 tries
// pass: the server sees the connections before it in its own time.
std::string answer_until(int port, int host, int status) {
  std::string answer;
  for (int i = 0; i < 20 && raw_status(answer) != status; ++i) {
    const int fd = start_upload(port, host, kLargest, kLargest);
    if (fd < 0) return "no connection from 127.0.0." + std::to_string(host);
    answer = raw_read_all(fd, 2000);
    ::close(fd);
  }
  return answer;
}

// causticd_http_errors_total from GET /metrics (-1 when it is not there).
long long http_errors(const ServerProcess& server) {
  const std::string text = http("GET", server.url() + "/metrics").body;
  const std::string name = "\ncausticd_http_errors_total ";
  const auto at = text.find(name);
  return at == std::string::npos ? -1 : std::stoll(text.substr(at + name.size()));
}

}  // namespace

TEST(Hardening, PicturesArrivingAtOnceAreBoundedPerAddressAndInAll) {
  ServerProcess server({"--set", "design_max_upload_bytes=" + std::to_string(kLargest)});
  // One picture of the largest size arrives slowly from 127.0.0.1: a second
  // from there must wait, with a reason and when to try again.
  std::vector<int> holding = {start_upload(server.port(), 1, kLargest, 1000)};
  ASSERT_GE(holding.back(), 0);
  std::string answer = answer_until(server.port(), 1, 503);
  expect_problem_answer(answer, 503);
  EXPECT_EQ(raw_header(answer, "Retry-After"), "2");
  EXPECT_NE(answer.find("a picture from your address is still arriving"), std::string::npos) << answer;
  // Another address still uploads (the bytes are no picture: 415).
  expect_problem_answer(answer_until(server.port(), 2, 415), 415);
  // Four slow pictures in all (the limit, kUploadsAtOnce): a fifth address waits too.
  for (int host = 3; host <= 5; ++host) {
    holding.push_back(start_upload(server.port(), host, kLargest, 1000));
    ASSERT_GE(holding.back(), 0);
  }
  answer = answer_until(server.port(), 6, 503);
  expect_problem_answer(answer, 503);
  EXPECT_NE(answer.find("too many pictures are arriving at once"), std::string::npos) << answer;
  // Once they are gone, pictures come in again.
  for (const int fd : holding) ::close(fd);
  expect_problem_answer(answer_until(server.port(), 6, 415), 415);
  expect_problem_answer(answer_until(server.port(), 1, 415), 415);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Hardening, AProxysVisitorsSendPicturesSideBySide) {
  // Behind a trusted proxy every picture comes from its address: the limit
  // in all holds, the one per address would have let one visitor at a time.
  ServerProcess server({"--set", "design_max_upload_bytes=" + std::to_string(kLargest), "--set",
                        "trusted_proxies=127.0.0.1"});
  const int slow = start_upload(server.port(), 1, kLargest, 1000);
  ASSERT_GE(slow, 0);
  // Its own second picture is not held up (the bytes are no picture: 415).
  expect_problem_answer(answer_until(server.port(), 1, 415), 415);
  ::close(slow);
}

// A body that stops half-way, cut off by either timeout: the client is told
// which (a 408 problem), not just disconnected, and the metrics count it
// among the error answers either way. One connection each.
TEST(Hardening, ABodyThatStopsComingIsAnswered408) {
  for (const char* timeout : {"body_timeout_s", "connection_idle_timeout_s"}) {
    const bool idle = std::string(timeout) == "connection_idle_timeout_s";
    ServerProcess server({"--set", std::string(idle ? "body_timeout_s" : "connection_idle_timeout_s") + "=60",
                          "--set", std::string(timeout) + "=1"});
    const long long errors = http_errors(server);
    ASSERT_GE(errors, 0);
    const int fd = raw_connect(server.port());
    ASSERT_GE(fd, 0);
    raw_send(fd, request_text("POST", "/api/v1/sessions", "Content-Type: application/json\r\nContent-Length: 100\r\n") +
                     "{\"scene\": ");
    bool closed = false;
    const std::string answer = raw_read_all(fd, 20000, &closed);
    ::close(fd);
    EXPECT_TRUE(closed) << timeout;
    expect_problem_answer(answer, 408);
    EXPECT_NE(raw_body(answer).find(timeout), std::string::npos) << answer;
    EXPECT_EQ(http_errors(server), errors + 1) << timeout;
    EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
  }
}

// A body cut short by the client's half-close will never finish: it is
// answered 400 at once, as a head cut short is, rather than closed without
// a word (or at a timeout, set here far longer than the test waits). A
// whole body followed by a half-close is served as any other. Each 400 is
// counted among the error answers.
TEST(Hardening, ABodyCutShortByTheClientIsAnsweredAtOnce) {
  ServerProcess server({"--set", "body_timeout_s=600", "--set", "connection_idle_timeout_s=600"});
  const long long errors = http_errors(server);
  ASSERT_GE(errors, 0);
  for (const std::string type : {"application/json", "image/png"}) {
    const int fd = raw_connect(server.port());
    ASSERT_GE(fd, 0);
    const std::string path = type == "image/png" ? "/api/v1/designs" : "/api/v1/sessions";
    raw_send(fd, request_text("POST", path, "Content-Type: " + type + "\r\nContent-Length: 100\r\n") + "{\"scene\": ");
    ::shutdown(fd, SHUT_WR);
    expect_problem_then_close(fd, 400, 30000);
  }
  EXPECT_EQ(http_errors(server), errors + 2);
  const int fd = raw_connect(server.port());
  ASSERT_GE(fd, 0);
  raw_send(fd, request_text("POST", "/api/v1/sessions", "Content-Type: application/json\r\n", R"({"scene": "lens"})"));
  ::shutdown(fd, SHUT_WR);
  const std::string answer = raw_read_all(fd, 30000);
  ::close(fd);
  EXPECT_EQ(raw_status(answer), 201) << answer.substr(0, 300);
}

// A picture's larger limit is chosen from the head, before the body is
// read, by the path the router will see however it was written, and behind
// a proxy with the instance's prefix (docs/api.md: "as without the
// prefix"): the same answer as the plain path, not 413 at 64 KiB. A path
// that routes elsewhere keeps the small limit.
TEST(Hardening, APictureIsTakenByEveryPathThatRoutesToUploads) {
  ServerProcess server({"--set", "instance_index=1"});
  const std::string body(100 * 1024, 'p');  // over max_body_bytes (64 KiB), under design_max_upload_bytes
  const auto status = [&](const std::string& path) {
    const std::string answer = raw_request(server.port(), "POST", path, "Content-Type: image/png\r\n", body);
    return raw_status(answer);
  };
  const int plain = status("/api/v1/designs");
  EXPECT_NE(plain, 413);
  for (const char* path : {"/api/v1/%64esigns", "/api/v1/./designs", "/api/v1/%64esigns?name=x", "/i/1/api/v1/designs"})
    EXPECT_EQ(status(path), plain) << path;
  EXPECT_EQ(status("/api/v1/sessions"), 413);
  EXPECT_EQ(status("/i/2/api/v1/designs"), 413);  // another instance's: not this one's route
}
