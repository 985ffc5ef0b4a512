// SPDX-License-Identifier: LGPL-2.1-or-later
// A PNG's chunks walked, and their checksums checked, before its reader
// sees it: libpng prints each error on stderr itself ("libpng error: ...")
// beside the one line the refusal says, and the image library gives it no
// way to be quiet. A file cut short or with a damaged byte fails here,
// named; libpng then reads only whole files.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace caustic::design {

// The CRC-32 of ISO 3309 that every PNG chunk ends with (PNG spec, annex D).
inline std::uint32_t png_crc(std::uint32_t crc, const unsigned char* bytes, std::size_t n) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ bytes[i]) & 0xff] ^ (crc >> 8);
  return crc;
}

/// Why the PNG read from `in` is damaged, in words for a message; "" when
/// its chunks are whole, each checksum right, and an IEND ends them, or
/// when it is no PNG at all (its own reader judges it). An animated PNG's
/// frame count (its acTL chunk's) goes to `frames`, which is left as it is
/// for any other.
inline std::string png_damage(std::istream& in, std::uint32_t* frames = nullptr) {
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  unsigned char head[8] = {};
  if (!in.read(reinterpret_cast<char*>(head), 8) || !std::equal(head, head + 8, signature)) return "";
  std::vector<unsigned char> data(1 << 16);
  for (std::uint64_t at = 8, chunks = 0;; ++chunks) {
    if (!in.read(reinterpret_cast<char*>(head), 8))
      return "cut short: it ends at byte " + std::to_string(at) + ", before its IEND chunk";
    const std::uint32_t length = std::uint32_t{head[0]} << 24 | head[1] << 16 | head[2] << 8 | head[3];
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    for (const char c : type)
      if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')))
        return "byte " + std::to_string(at) + " holds no chunk";
    if (chunks == 0 && type != "IHDR") return "it does not begin with its IHDR chunk";
    if (length > 0x7fffffffu) return "the " + type + " chunk at byte " + std::to_string(at) + " claims " +
                                     std::to_string(length) + " bytes, more than PNG allows";
    std::uint32_t crc = png_crc(0xffffffffu, head + 4, 4);
    for (std::uint32_t left = length; left > 0;) {
      const std::uint32_t n = std::min<std::uint32_t>(left, static_cast<std::uint32_t>(data.size()));
      if (!in.read(reinterpret_cast<char*>(data.data()), n))
        return "cut short: the " + type + " chunk at byte " + std::to_string(at) + " runs past the end of the file";
      crc = png_crc(crc, data.data(), n);
      if (type == "acTL" && left == length && n >= 4 && frames)
        *frames = std::uint32_t{data[0]} << 24 | data[1] << 16 | data[2] << 8 | data[3];
      left -= n;
    }
    unsigned char stored[4] = {};
    if (!in.read(reinterpret_cast<char*>(stored), 4))
      return "cut short: the " + type + " chunk at byte " + std::to_string(at) + " runs past the end of the file";
    const std::uint32_t expected = std::uint32_t{stored[0]} << 24 | stored[1] << 16 | stored[2] << 8 | stored[3];
    if ((crc ^ 0xffffffffu) != expected)
      return "the " + type + " chunk at byte " + std::to_string(at) + " fails its checksum";
    if (type == "IEND") return "";
    at += 12 + std::uint64_t{length};
  }
}

}  // namespace caustic::design
