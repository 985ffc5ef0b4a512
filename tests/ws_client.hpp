// SPDX-License-Identifier: LGPL-2.1-or-later
// A minimal WebSocket client over a raw socket, for frames a browser would
// never send (fragments past the limits) and for peers that fall silent.
#pragma once

#include "raw_http.hpp"

#include <cstdint>
#include <optional>
#include <random>
#include <string>

namespace caustic::testing {

/// Opens `path` (with its query) as a WebSocket; -1 unless the server
/// answered 101, and then, when `refusal` is given, the server's whole
/// answer (head and body) in it.
inline int ws_open(int port, const std::string& path, std::string* refusal = nullptr) {
  const int fd = raw_connect(port);
  if (fd < 0) return -1;
  raw_send(fd, "GET " + path +
                   " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                   "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  std::string head;
  char ch;
  // Byte by byte up to the blank line, so no frame is swallowed.
  while (head.size() < 4096 && head.find("\r\n\r\n") == std::string::npos) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 10000) <= 0 || ::recv(fd, &ch, 1, 0) != 1) break;
    head += ch;
  }
  if (raw_status(head) != 101) {
    if (refusal) *refusal = head + raw_read_all(fd, 10000);
    ::close(fd);
    return -1;
  }
  return fd;
}

/// Sends one masked client frame.
inline bool ws_send_frame(int fd, unsigned opcode, bool fin, const std::string& payload) {
  std::string frame;
  frame += static_cast<char>((fin ? 0x80 : 0) | (opcode & 0x0f));
  const std::uint64_t n = payload.size();
  if (n < 126) {
    frame += static_cast<char>(0x80 | n);
  } else if (n < 65536) {
    frame += static_cast<char>(0x80 | 126);
    frame += static_cast<char>(n >> 8);
    frame += static_cast<char>(n & 0xff);
  } else {
    frame += static_cast<char>(0x80 | 127);
    for (int i = 7; i >= 0; --i) frame += static_cast<char>((n >> (8 * i)) & 0xff);
  }
  const unsigned char mask[4] = {0x12, 0x34, 0x56, 0x78};
  frame.append(reinterpret_cast<const char*>(mask), 4);
  for (std::size_t i = 0; i < payload.size(); ++i) frame += static_cast<char>(payload[i] ^ mask[i % 4]);
  return raw_send(fd, frame);
}

/// The next text message from the server (unfragmented frames), or none
/// within `timeout_ms` or when the socket closed.
inline std::optional<std::string> ws_read_text(int fd, int timeout_ms) {
  std::string buffer;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  auto need = [&](std::size_t n) {
    while (buffer.size() < n && std::chrono::steady_clock::now() < end) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 100) <= 0) continue;
      char buf[65536];
      // Only what the frame needs: the rest stays for the next call.
      const ssize_t got = ::recv(fd, buf, std::min(sizeof buf, n - buffer.size()), 0);
      if (got <= 0) return false;
      buffer.append(buf, static_cast<std::size_t>(got));
    }
    return buffer.size() >= n;
  };
  while (true) {
    buffer.clear();
    if (!need(2)) return std::nullopt;
    const unsigned opcode = static_cast<unsigned char>(buffer[0]) & 0x0f;
    std::uint64_t len = static_cast<unsigned char>(buffer[1]) & 0x7f;
    std::size_t header = 2;
    if (len == 126) {
      if (!need(4)) return std::nullopt;
      len = (std::uint64_t(static_cast<unsigned char>(buffer[2])) << 8) | static_cast<unsigned char>(buffer[3]);
      header = 4;
    } else if (len == 127) {
      if (!need(10)) return std::nullopt;
      len = 0;
      for (int i = 0; i < 8; ++i) len = (len << 8) | static_cast<unsigned char>(buffer[2 + i]);
      header = 10;
    }
    if (len > (1u << 24) || !need(header + len)) return std::nullopt;
    if (opcode == 1) return buffer.substr(header, len);
    if (opcode == 8) return std::nullopt;  // close
  }
}

}  // namespace caustic::testing
