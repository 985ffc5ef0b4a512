// SPDX-License-Identifier: LGPL-2.1-or-later
// A minimal WebSocket client over a raw socket, for frames a browser would
// never send (fragments past the limits) and for peers that fall silent.
#pragma once

#include "raw_http.hpp"

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <string_view>

namespace caustic::testing {

/// The fields that ask for a WebSocket (RFC 6455), in pieces for the
/// handshakes that leave one out or spell it wrong.
inline const std::string kWsUpgrade = "Upgrade: websocket\r\nConnection: Upgrade\r\n";
inline const std::string kWsVersion = "Sec-WebSocket-Version: 13\r\n";
inline const std::string kWsSampleKey = "dGhlIHNhbXBsZSBub25jZQ==";  // RFC 6455's own example
inline std::string ws_key_field(const std::string& key = kWsSampleKey) { return "Sec-WebSocket-Key: " + key + "\r\n"; }

/// A client's opening handshake for `target`, `extra` fields added.
inline std::string ws_upgrade_request(const std::string& target, const std::string& key = kWsSampleKey,
                                      const std::string& extra = "") {
  return request_text("GET", target, kWsUpgrade + ws_key_field(key) + kWsVersion + extra);
}

/// Opens `path` (with its query) as a WebSocket; -1 unless the server
/// answered 101, and then, when `refusal` is given, the server's whole
/// answer (head and body) in it.
inline int ws_open(int port, const std::string& path, std::string* refusal = nullptr) {
  const int fd = raw_connect(port);
  if (fd < 0) return -1;
  raw_send(fd, ws_upgrade_request(path));
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

/// One frame's bytes, masked with the four bytes of `mask` as a client's
/// must be, or unmasked (as a server's) when it is null.
inline std::string ws_frame_bytes(unsigned opcode, bool fin, std::string_view payload, const unsigned char* mask) {
  std::string frame;
  frame += static_cast<char>((fin ? 0x80 : 0) | (opcode & 0x0f));
  const unsigned char mask_bit = mask ? 0x80 : 0;
  const std::uint64_t n = payload.size();
  if (n < 126) {
    frame += static_cast<char>(mask_bit | n);
  } else if (n < 65536) {
    frame += static_cast<char>(mask_bit | 126);
    frame += static_cast<char>(n >> 8);
    frame += static_cast<char>(n & 0xff);
  } else {
    frame += static_cast<char>(mask_bit | 127);
    for (int i = 7; i >= 0; --i) frame += static_cast<char>((n >> (8 * i)) & 0xff);
  }
  if (mask) frame.append(reinterpret_cast<const char*>(mask), 4);
  for (std::size_t i = 0; i < n; ++i) frame += static_cast<char>(payload[i] ^ (mask ? mask[i % 4] : 0));
  return frame;
}

/// Sends one masked client frame.
inline bool ws_send_frame(int fd, unsigned opcode, bool fin, const std::string& payload) {
  static const unsigned char mask[4] = {0x12, 0x34, 0x56, 0x78};
  return raw_send(fd, ws_frame_bytes(opcode, fin, payload, mask));
}

/// A frame's header size (2, 4 or 10 bytes, a mask not counted) from its
/// first two bytes, and the payload's length from the whole header.
inline std::size_t ws_header_size(std::string_view first_two) {
  const unsigned n = static_cast<unsigned char>(first_two[1]) & 0x7f;
  return n == 126 ? 4 : n == 127 ? 10 : 2;
}
inline std::uint64_t ws_payload_length(std::string_view header) {
  const std::size_t size = ws_header_size(header);
  if (size == 2) return static_cast<unsigned char>(header[1]) & 0x7f;
  std::uint64_t n = 0;
  for (std::size_t i = 2; i < size; ++i) n = (n << 8) | static_cast<unsigned char>(header[i]);
  return n;
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
    const std::size_t header = ws_header_size(buffer);
    if (!need(header)) return std::nullopt;
    const std::uint64_t len = ws_payload_length(buffer);
    if (len > (1u << 24) || !need(header + len)) return std::nullopt;
    if (opcode == 1) return buffer.substr(header, len);
    if (opcode == 8) return std::nullopt;  // close
  }
}

}  // namespace caustic::testing
