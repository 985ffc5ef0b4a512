// SPDX-License-Identifier: LGPL-2.1-or-later
// Text shown to people as it was written (a scene's title and description,
// a design's name), checked alike by the scene parser, the designer's flags
// and an upload's query. Besides ASCII's control characters, Unicode's C1
// controls (U+0080-U+009F, NEL among them), the line and paragraph
// separators (U+2028, U+2029: a line break in one character) and the
// bidirectional embeddings, overrides and isolates (U+202A-U+202E,
// U+2066-U+2069, which reorder what follows them on a page: "gpj.exe"
// shown as "exe.jpg") are refused; each of them was let through.
#pragma once

#include <cstddef>
#include <string_view>

namespace caustic {

/// Whether `text` (UTF-8) holds a character that must not be shown as written.
inline bool holds_control_characters(std::string_view text) {
  const auto byte = [&](std::size_t i) { return i < text.size() ? static_cast<unsigned char>(text[i]) : 0u; };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned c = byte(i), next = byte(i + 1), last = byte(i + 2);
    if (c < 0x20 || c == 0x7f) return true;
    if (c == 0xc2 && next >= 0x80 && next <= 0x9f) return true;  // U+0080-U+009F
    if (c == 0xe2 && next == 0x80 && last >= 0xa8 && last <= 0xae) return true;  // U+2028-U+202E
    if (c == 0xe2 && next == 0x81 && last >= 0xa6 && last <= 0xa9) return true;  // U+2066-U+2069
  }
  return false;
}

}  // namespace caustic
