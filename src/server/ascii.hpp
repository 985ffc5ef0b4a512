// SPDX-License-Identifier: LGPL-2.1-or-later
// Case-folding for the protocol words the server reads (SDP attribute and
// hash names, transports, CAUSTICD_ variable names): ASCII only, whatever
// the process locale says, since these are case-insensitive by their specs
// and never text in a visitor's language.
#pragma once

#include <string>

namespace caustic::server {

inline std::string ascii_lower(std::string text) {
  for (char& c : text)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return text;
}

}  // namespace caustic::server
