// SPDX-License-Identifier: LGPL-2.1-or-later
// Case-folding and hex digits for the protocol words the server reads (SDP
// attribute and hash names, transports, CAUSTICD_ variable names, percent-
// escapes, fingerprints): ASCII only, whatever the process locale says,
// since these are case-insensitive by their specs and never text in a
// visitor's language.
#pragma once

#include <string>

namespace caustic::server {

inline std::string ascii_lower(std::string text) {
  for (char& c : text)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return text;
}

/// The value of hex digit `c` (either case); -1 for any other character.
inline int ascii_hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

}  // namespace caustic::server
