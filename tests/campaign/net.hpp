// SPDX-License-Identifier: LGPL-2.1-or-later
// Raw loopback HTTP/1.1 and WebSocket client for the fault campaign. It is
// written on bare POSIX sockets so that it can send bytes no HTTP library
// would produce; every call takes a deadline so no step can hang the run.
#pragma once

#include "../raw_http.hpp"

#include <chrono>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace campaign {

// Requests whose fields are written out as they go on the wire.
using caustic::testing::request_text;

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start);

// An owned socket plus the bytes read from it but not used yet (a server may
// send a WebSocket frame in the same segment as its 101 answer).
struct Conn {
  int fd = -1;
  std::string pending;
  Conn() = default;
  explicit Conn(int f) : fd(f) {}
  Conn(Conn&& o) noexcept : fd(o.fd), pending(std::move(o.pending)) { o.fd = -1; }
  Conn& operator=(Conn&& o) noexcept;
  Conn(const Conn&) = delete;
  Conn& operator=(const Conn&) = delete;
  ~Conn() { close(); }
  void close();
  // Closes with RST instead of FIN, like a client that crashed.
  void abort();
  bool ok() const { return fd >= 0; }
};

// Connects to 127.0.0.1:port, optionally from another loopback source
// address (127.0.0.0/8 is all local), so per-address limits can be told
// apart from global ones.
Conn connect_loopback(int port, const std::string& source = "", int timeout_ms = 3000);

bool send_all(Conn& c, std::string_view bytes, int timeout_ms = 3000);

// Acknowledge every segment at once. A server that writes an answer in
// small pieces without TCP_NODELAY otherwise waits for our delayed ACK
// (about 40 ms a request); kinds that count requests rather than time them
// turn this on so that the run fits its budget.
void set_quick_ack(bool on);

// What came back for one request.
struct Response {
  enum Kind { Answer, Closed, Timeout, Garbage, ConnectFailed } kind = Closed;
  int status = 0;
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;
  double ms = 0;                                    // from the end of sending to the complete answer
  std::string header(std::string_view name) const;  // "" when absent
  bool has_header(std::string_view name) const;
};

const char* kind_name(Response::Kind k);

// Reads one response. `head`: the request was HEAD (no body follows).
Response read_response(Conn& c, int timeout_ms, bool head = false);

// True when the peer closes (EOF or reset) within timeout_ms.
bool wait_closed(Conn& c, int timeout_ms);

// One request on a fresh connection. `half_close`: shut our sending side
// after the bytes, for requests that promise more body than they carry.
Response exchange(int port, std::string_view request, int timeout_ms, bool head = false, bool half_close = false,
                  const std::string& source = "", Conn* keep = nullptr);

// Convenience: a well-formed request with Connection: close (unless
// `headers` name their own), its fields given as pairs.
std::string make_request(const std::string& method, const std::string& target,
                         const std::vector<std::pair<std::string, std::string>>& headers = {},
                         const std::string& body = "");

// Printable rendering of arbitrary bytes for the failure log.
std::string escape(std::string_view bytes, std::size_t limit = 600);

// WebSocket client pieces (RFC 6455).
std::string ws_handshake(const std::string& target, std::mt19937& rng, const std::string& extra = "");
std::string ws_frame(int opcode, std::string_view payload, bool fin, std::mt19937& rng, bool masked = true);
struct WsFrame {
  bool ok = false;  // false: closed, timed out or not a frame
  bool timeout = false;
  int opcode = 0;
  std::string payload;
};
WsFrame ws_read(Conn& c, int timeout_ms);

}  // namespace campaign
