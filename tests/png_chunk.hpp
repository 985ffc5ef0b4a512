// SPDX-License-Identifier: LGPL-2.1-or-later
// A PNG chunk made by hand, for tests that build PNG files byte by byte
// (an animated PNG's acTL, a chunk cut short, a wrong CRC).
#pragma once

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

/// `png` (a whole file) made an animated PNG of `frames` frames, played for
/// ever: its acTL chunk put after IHDR (which ends at byte 33).
inline std::string animated_png(const std::string& png, std::uint32_t frames) {
  const std::string count{static_cast<char>(frames >> 24), static_cast<char>(frames >> 16), static_cast<char>(frames >> 8),
                          static_cast<char>(frames), 0, 0, 0, 0};
  return png.substr(0, 33) + png_chunk("acTL", count) + png.substr(33);
}

}  // namespace caustic::testing
