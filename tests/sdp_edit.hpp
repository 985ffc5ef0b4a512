// SPDX-License-Identifier: LGPL-2.1-or-later
// Hand-edited session descriptions for the tests that refuse answers which
// do not fit the offer: the edits are plain text replacements of lines.
#pragma once

#include <string>

namespace caustic::testing {

/// `text` with every `from` replaced by `to`, left to right, never
/// rescanning what was put in.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) text.replace(at, from.size(), to);
  return text;
}

}  // namespace caustic::testing
