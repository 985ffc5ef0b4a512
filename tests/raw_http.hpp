// SPDX-License-Identifier: LGPL-2.1-or-later
// Requests written byte for byte over loopback, for what an HTTP library
// would refuse to send: broken heads, lying lengths, slow or idle clients.
// Every wait is bounded.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <string>

namespace caustic::testing {

/// A connected socket to 127.0.0.1:port, or -1 when none within
/// `timeout_ms` (a full backlog would otherwise hold a blocking connect for
/// minutes). From the loopback address `source` when given: all of
/// 127.0.0.0/8 is local, so per-address limits can be told apart.
inline int raw_connect(int port, const std::string& source = "", int timeout_ms = 10000) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return -1;
  sockaddr_in from{};
  from.sin_family = AF_INET;
  bool ok = source.empty() || (::inet_pton(AF_INET, source.c_str(), &from.sin_addr) == 1 &&
                               ::bind(fd, reinterpret_cast<sockaddr*>(&from), sizeof from) == 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // never anything but loopback
  if (ok && ::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
    pollfd p{fd, POLLOUT, 0};
    int error = 0;
    socklen_t size = sizeof error;
    ok = errno == EINPROGRESS && ::poll(&p, 1, timeout_ms) == 1 &&
         ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &size) == 0 && error == 0;
  }
  if (!ok) {
    ::close(fd);
    return -1;
  }
  // Blocking again: every read here polls first, with its own bound.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

/// A connected socket to the Unix stream socket at `path`, or -1.
inline int raw_connect_unix(const std::string& path) {
  sockaddr_un to{};
  if (path.size() >= sizeof to.sun_path) return -1;
  to.sun_family = AF_UNIX;
  path.copy(to.sun_path, path.size());
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

/// Whether something listens on 127.0.0.1:port within `timeout_ms`: a
/// program just started listens once it is ready.
inline bool raw_wait_listening(int port, int timeout_ms = 10000) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  do {
    if (const int fd = raw_connect(port, "", timeout_ms); fd >= 0) {
      ::close(fd);
      return true;
    }
    ::usleep(100000);
  } while (std::chrono::steady_clock::now() < end);
  return false;
}

inline bool raw_send(int fd, const std::string& bytes) {
  return ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
}

/// Everything the server sends until it closes, or until `timeout_ms` pass.
/// `closed` tells which of the two ended it.
inline std::string raw_read_all(int fd, int timeout_ms, bool* closed = nullptr) {
  std::string out;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  if (closed) *closed = false;
  while (std::chrono::steady_clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (::poll(&p, 1, static_cast<int>(std::max<long long>(1, left.count()))) <= 0) continue;
    char buf[8192];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) {
      if (closed) *closed = true;
      break;
    }
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

/// Sends `bytes` on the connected `fd` (nothing when empty: a peer that
/// speaks first), returns all it answers until it closes or `timeout_ms`
/// pass, and closes `fd`; "" when `fd` is -1.
inline std::string raw_exchange(int fd, const std::string& bytes, int timeout_ms = 10000) {
  if (fd < 0) return "";
  if (!bytes.empty()) raw_send(fd, bytes);
  std::string answer = raw_read_all(fd, timeout_ms);
  ::close(fd);
  return answer;
}

/// Sends `bytes` on a fresh connection and returns the whole answer.
inline std::string raw_request(int port, const std::string& bytes, int timeout_ms = 10000) {
  return raw_exchange(raw_connect(port), bytes, timeout_ms);
}

/// A well-formed request as its bytes: the request line, Host, `fields`
/// (each ending in "\r\n"), and the body after its Content-Length when
/// there is one. What a test means to break it writes itself.
inline std::string request_text(const std::string& method, const std::string& target, const std::string& fields = "",
                                const std::string& body = "") {
  return method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + fields +
         (body.empty() ? "" : "Content-Length: " + std::to_string(body.size()) + "\r\n") + "\r\n" + body;
}

/// That request on a fresh connection (the server closes each after its
/// answer), and the whole answer: for targets and fields, byte for byte,
/// that an HTTP library would normalise or refuse to send.
inline std::string raw_request(int port, const std::string& method, const std::string& target,
                               const std::string& fields = "", const std::string& body = "") {
  return raw_request(port, request_text(method, target, fields, body));
}

/// The status code of an HTTP answer, 0 when there is none.
inline int raw_status(const std::string& answer) {
  if (answer.rfind("HTTP/1.", 0) != 0 || answer.size() < 12) return 0;
  return std::stoi(answer.substr(9, 3));
}

/// The body after the blank line.
inline std::string raw_body(const std::string& answer) {
  const auto end = answer.find("\r\n\r\n");
  return end == std::string::npos ? "" : answer.substr(end + 4);
}

/// A header's value (case-insensitive name), "" when absent.
inline std::string raw_header(const std::string& answer, const std::string& name) {
  const auto head_end = answer.find("\r\n\r\n");
  std::size_t pos = answer.find("\r\n");
  while (pos != std::string::npos && pos < head_end) {
    const auto eol = answer.find("\r\n", pos + 2);
    const std::string line = answer.substr(pos + 2, eol - pos - 2);
    const auto colon = line.find(':');
    if (colon != std::string::npos && strncasecmp(line.c_str(), name.c_str(), name.size()) == 0 && colon == name.size())
      return line.substr(line.find_first_not_of(' ', colon + 1));
    pos = eol;
  }
  return "";
}

/// Open descriptors of a process.
inline int open_descriptors(const std::string& pid) {
  int n = 0;
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/" + pid + "/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++n;
  return n;
}

}  // namespace caustic::testing
