// SPDX-License-Identifier: LGPL-2.1-or-later
#include "net.hpp"

#include "../ws_client.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>

namespace campaign {

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

Conn& Conn::operator=(Conn&& o) noexcept {
  if (this != &o) {
    close();
    fd = o.fd;
    pending = std::move(o.pending);
    o.fd = -1;
  }
  return *this;
}

void Conn::close() {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

void Conn::abort() {
  if (fd < 0) return;
  linger l{1, 0};
  setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof l);
  close();
}

Conn connect_loopback(int port, const std::string& source, int timeout_ms) {
  Conn c(caustic::testing::raw_connect(port, source, timeout_ms));
  if (!c.ok()) return c;
  // Non-blocking: every read and write here waits in poll() with its own deadline.
  fcntl(c.fd, F_SETFL, fcntl(c.fd, F_GETFL) | O_NONBLOCK);
  const int one = 1;
  setsockopt(c.fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return c;
}

namespace {
std::atomic<bool> quick_ack{false};
}  // namespace

void set_quick_ack(bool on) { quick_ack = on; }

bool send_all(Conn& c, std::string_view bytes, int timeout_ms) {
  const auto start = Clock::now();
  while (!bytes.empty()) {
    const ssize_t n = send(c.fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n > 0) {
      bytes.remove_prefix(static_cast<size_t>(n));
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return false;
    const int left = timeout_ms - static_cast<int>(ms_since(start));
    if (left <= 0) return false;
    pollfd p{c.fd, POLLOUT, 0};
    if (poll(&p, 1, left) <= 0) return false;
  }
  return true;
}

namespace {

Response read_one(Conn& c, int timeout_ms, bool head);

// Appends what arrives within the deadline; false on EOF/error/timeout.
enum class Fill { Data, Eof, Timeout };
Fill fill(Conn& c, Clock::time_point deadline) {
  char buf[65536];
  const int one = 1;
  for (;;) {
    if (quick_ack) setsockopt(c.fd, IPPROTO_TCP, TCP_QUICKACK, &one, sizeof one);
    const ssize_t n = recv(c.fd, buf, sizeof buf, 0);
    if (n > 0) {
      c.pending.append(buf, static_cast<size_t>(n));
      return Fill::Data;
    }
    if (n == 0) return Fill::Eof;
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return Fill::Eof;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return Fill::Timeout;
    if (quick_ack) setsockopt(c.fd, IPPROTO_TCP, TCP_QUICKACK, &one, sizeof one);
    pollfd p{c.fd, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left)) == 0) return Fill::Timeout;
  }
}

std::string lower(std::string s) {
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

}  // namespace

std::string Response::header(std::string_view name) const {
  const std::string want = lower(std::string(name));
  for (const auto& [k, v] : headers)
    if (lower(k) == want) return v;
  return "";
}

bool Response::has_header(std::string_view name) const {
  const std::string want = lower(std::string(name));
  return std::any_of(headers.begin(), headers.end(), [&](const auto& h) { return lower(h.first) == want; });
}

const char* kind_name(Response::Kind k) {
  switch (k) {
    case Response::Answer:
      return "answer";
    case Response::Closed:
      return "closed-without-answer";
    case Response::Timeout:
      return "timeout";
    case Response::Garbage:
      return "garbage";
    case Response::ConnectFailed:
      return "connect-failed";
  }
  return "?";
}

Response read_response(Conn& c, int timeout_ms, bool head) {
  // Interim answers (100 Continue) precede the real one.
  const auto start = Clock::now();
  for (;;) {
    const int left = timeout_ms - static_cast<int>(ms_since(start));
    Response r = read_one(c, std::max(left, 1), head);
    if (r.kind != Response::Answer || r.status < 100 || r.status >= 200 || r.status == 101) {
      r.ms = ms_since(start);
      return r;
    }
  }
}

namespace {

Response read_one(Conn& c, int timeout_ms, bool head) {
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::milliseconds(timeout_ms);
  Response r;
  size_t end = std::string::npos;
  for (;;) {
    end = c.pending.find("\r\n\r\n");
    if (end != std::string::npos) break;
    if (c.pending.size() >= 5 && c.pending.compare(0, 5, "HTTP/") != 0) {
      r.kind = Response::Garbage;
      return r;
    }
    if (c.pending.size() > (1u << 20)) {
      r.kind = Response::Garbage;
      return r;
    }
    const Fill f = fill(c, deadline);
    if (f == Fill::Timeout) {
      r.kind = Response::Timeout;
      return r;
    }
    if (f == Fill::Eof) {
      r.kind = c.pending.empty() ? Response::Closed : Response::Garbage;
      return r;
    }
  }
  const std::string head_text = c.pending.substr(0, end);
  c.pending.erase(0, end + 4);
  size_t line_end = head_text.find("\r\n");
  const std::string status_line = head_text.substr(0, line_end);
  if (status_line.size() < 12 || status_line.compare(0, 5, "HTTP/") != 0) {
    r.kind = Response::Garbage;
    return r;
  }
  r.status = std::atoi(status_line.c_str() + 9);
  while (line_end != std::string::npos) {
    const size_t next = head_text.find("\r\n", line_end + 2);
    const std::string line =
        head_text.substr(line_end + 2, next == std::string::npos ? std::string::npos : next - line_end - 2);
    const auto colon = line.find(':');
    if (colon != std::string::npos) r.headers.emplace_back(trim(line.substr(0, colon)), trim(line.substr(colon + 1)));
    line_end = next;
  }
  r.kind = Response::Answer;
  const bool no_body = head || r.status == 204 || r.status == 304 || r.status == 101 || r.status / 100 == 1;
  if (!no_body) {
    if (lower(r.header("Transfer-Encoding")).find("chunked") != std::string::npos) {
      // Chunked: size line, data, CRLF, ... 0 CRLF CRLF.
      for (;;) {
        size_t eol;
        while ((eol = c.pending.find("\r\n")) == std::string::npos)
          if (fill(c, deadline) != Fill::Data) return r.kind = Response::Timeout, r;
        const size_t size = std::strtoul(c.pending.c_str(), nullptr, 16);
        while (c.pending.size() < eol + 2 + size + 2)
          if (fill(c, deadline) != Fill::Data) return r.kind = Response::Timeout, r;
        r.body += c.pending.substr(eol + 2, size);
        c.pending.erase(0, eol + 2 + size + 2);
        if (size == 0) break;
      }
    } else if (r.has_header("Content-Length")) {
      const size_t length = std::strtoul(r.header("Content-Length").c_str(), nullptr, 10);
      while (c.pending.size() < length) {
        const Fill f = fill(c, deadline);
        if (f != Fill::Data) return r.kind = (f == Fill::Timeout ? Response::Timeout : Response::Garbage), r;
      }
      r.body = c.pending.substr(0, length);
      c.pending.erase(0, length);
    } else {
      // Delimited by close: bounded by the deadline.
      while (fill(c, deadline) == Fill::Data) {
      }
      r.body = std::move(c.pending);
      c.pending.clear();
    }
  }
  r.ms = ms_since(start);
  return r;
}

}  // namespace

bool wait_closed(Conn& c, int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const Fill f = fill(c, deadline);
    if (f == Fill::Eof) return true;
    if (f == Fill::Timeout) return false;
    if (c.pending.size() > (1u << 20)) c.pending.clear();  // keep reading, bounded memory
  }
}

Response exchange(int port, std::string_view request, int timeout_ms, bool head, bool half_close,
                  const std::string& source, Conn* keep) {
  Conn c = connect_loopback(port, source);
  Response r;
  if (!c.ok()) {
    r.kind = Response::ConnectFailed;
    return r;
  }
  const auto start = Clock::now();
  // A server may answer and close before taking the whole request (a 413
  // on the headers alone): a failed send still reads what came back.
  send_all(c, request, timeout_ms);
  if (half_close) shutdown(c.fd, SHUT_WR);
  r = read_response(c, timeout_ms, head);
  r.ms = ms_since(start);
  if (keep) *keep = std::move(c);
  return r;
}

std::string make_request(const std::string& method, const std::string& target,
                         const std::vector<std::pair<std::string, std::string>>& headers, const std::string& body) {
  std::string fields;
  bool has_connection = false;
  for (const auto& [k, v] : headers) {
    fields += k + ": " + v + "\r\n";
    has_connection = has_connection || lower(k) == "connection";
  }
  if (!has_connection) fields += "Connection: close\r\n";
  // A POST or PATCH says its length even without a body.
  if (body.empty() && (method == "POST" || method == "PATCH")) fields += "Content-Length: 0\r\n";
  return request_text(method, target, fields, body);
}

std::string escape(std::string_view bytes, std::size_t limit) {
  std::string out;
  for (unsigned char ch : bytes) {
    if (out.size() >= limit) return out + "...(" + std::to_string(bytes.size()) + " bytes)";
    if (ch == '\r')
      out += "\\r";
    else if (ch == '\n')
      out += "\\n";
    else if (ch == '\\')
      out += "\\\\";
    else if (ch >= 0x20 && ch < 0x7f)
      out += static_cast<char>(ch);
    else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", ch);
      out += hex;
    }
  }
  return out;
}

std::string ws_handshake(const std::string& target, std::mt19937& rng, const std::string& extra) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string key;
  for (int i = 0; i < 21; ++i) key += alphabet[rng() % 64];
  key += "Q==";  // 16 bytes in base64: 22 characters (the last one holds 2 bits) and "=="
  return caustic::testing::ws_upgrade_request(target, key, extra);
}

std::string ws_frame(int opcode, std::string_view payload, bool fin, std::mt19937& rng, bool masked) {
  unsigned char mask[4];
  if (masked)
    for (auto& m : mask) m = static_cast<unsigned char>(rng());
  return caustic::testing::ws_frame_bytes(opcode, fin, payload, masked ? mask : nullptr);
}

WsFrame ws_read(Conn& c, int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  WsFrame out;
  auto need = [&](size_t n) {
    while (c.pending.size() < n) {
      const Fill f = fill(c, deadline);
      if (f != Fill::Data) {
        out.timeout = f == Fill::Timeout;
        return false;
      }
    }
    return true;
  };
  if (!need(2)) return out;
  const size_t header = caustic::testing::ws_header_size(c.pending);
  if (!need(header)) return out;
  const uint64_t n = caustic::testing::ws_payload_length(c.pending);
  if ((c.pending[1] & 0x80) || n > (16u << 20)) return out;  // servers never mask; bound memory
  if (!need(header + n)) return out;
  out.ok = true;
  out.opcode = static_cast<unsigned char>(c.pending[0]) & 0x0f;
  out.payload = c.pending.substr(header, n);
  c.pending.erase(0, header + n);
  return out;
}

}  // namespace campaign
