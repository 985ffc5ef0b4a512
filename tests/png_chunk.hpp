// SPDX-License-Identifier: LGPL-2.1-or-later
// A PNG chunk made by hand, for tests that build PNG files byte by byte
// (an animated PNG's acTL, a chunk cut short, a wrong CRC).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

namespace caustic::testing {

/// A PNG's chunk: length, type, data and its CRC-32 over type and data,
/// computed bit by bit as the PNG spec's annex D defines it.
inline std::string png_chunk(const std::string& type, const std::string& data) {
  std::uint32_t c = 0xffffffffu;
  for (const unsigned char b : type + data) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  std::string out;
  for (const std::uint32_t v : {static_cast<std::uint32_t>(data.size()), ~c})
    for (int k = 3; k >= 0; --k) out += static_cast<char>(v >> (8 * k));
  return out.substr(0, 4) + type + data + out.substr(4);
}

/// `raw` in zlib's format, in stored blocks (no compression), with its
/// Adler-32: image data whose every byte the test chose.
inline std::string zlib_stored(const std::string& raw) {
  std::string z("\x78\x01", 2);
  for (std::size_t at = 0; at == 0 || at < raw.size(); at += 65535) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    z += static_cast<char>(at + n == raw.size());  // the last block says so
    for (const std::size_t v : {n, ~n}) z += static_cast<char>(v & 0xff), z += static_cast<char>(v >> 8 & 0xff);
    z.append(raw, at, n);
  }
  std::uint32_t a = 1, b = 0;
  for (const unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  for (const std::uint32_t v : {b >> 8, b, a >> 8, a}) z += static_cast<char>(v);
  return z;
}

/// A PNG of `w` x `h` whose IHDR gives `depth` bits of `colour_type`
/// (0 grey, 2 RGB, 3 palette, 4 grey and alpha, 6 RGBA) and `interlace`
/// (0, or 1: Adam7), its image data `raw` (filter bytes and rows, as the
/// test lays them out) in one IDAT; `before_idat` (chunks) after the IHDR.
inline std::string png_file(std::uint32_t w, std::uint32_t h, int depth, int colour_type, int interlace,
                            const std::string& raw, const std::string& before_idat = "") {
  std::string ihdr;
  for (const std::uint32_t v : {w, h})
    for (int k = 3; k >= 0; --k) ihdr += static_cast<char>(v >> (8 * k));
  ihdr += {static_cast<char>(depth), static_cast<char>(colour_type), 0, 0, static_cast<char>(interlace)};
  return "\x89PNG\r\n\x1a\n" + png_chunk("IHDR", ihdr) + before_idat + png_chunk("IDAT", zlib_stored(raw)) +
         png_chunk("IEND", "");
}

/// `png` (a whole file) made an animated PNG of `frames` frames, played for
/// ever: its acTL chunk put after IHDR (which ends at byte 33).
inline std::string animated_png(const std::string& png, std::uint32_t frames) {
  const std::string count{static_cast<char>(frames >> 24), static_cast<char>(frames >> 16), static_cast<char>(frames >> 8),
                          static_cast<char>(frames), 0, 0, 0, 0};
  return png.substr(0, 33) + png_chunk("acTL", count) + png.substr(33);
}

}  // namespace caustic::testing
