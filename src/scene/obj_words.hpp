// SPDX-License-Identifier: LGPL-2.1-or-later
// The words of an OBJ line as the loader (tinyobjloader) reads them, for the
// check that runs before it (mesh_obj.cpp): what the check passes, the
// loader must read as the same value.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>

namespace caustic::detail {

inline bool digit(char ch) { return ch >= '0' && ch <= '9'; }

/// A face's corner: v, v/vt, v//vn or v/vt/vn, each a nonzero integer (a
/// negative one counts back from the last vertex) within an int.
inline bool face_corner(const std::string& word) {
  std::size_t at = 0;
  for (int part = 0; part < 3; ++part) {
    if (part > 0) {
      if (at == word.size()) return true;
      if (word[at] != '/') return false;
      ++at;
      if (part == 1 && at < word.size() && word[at] == '/') continue;  // v//vn
    }
    if (at < word.size() && word[at] == '-') ++at;
    const std::size_t digits = at;
    long long index = 0;  // at most 10 digits: no overflow
    for (; at < word.size() && digit(word[at]) && at - digits < 11; ++at) index = 10 * index + (word[at] - '0');
    if (at == digits || at - digits > 10 || index == 0 || index > 2147483647LL) return false;
  }
  return at == word.size();
}

/// A number as the loader reads it: [+-] digits [. digits] [e [+-] digits],
/// digits on one side of the point at least. strtod also takes hex
/// ("0x1p3" is 8) where the loader stops at the "x" and reads 0, a vertex
/// moved without a word; and the loader scales by 5^exponent, which is Inf
/// past e441 (NaN for a zero: "0e500", which strtod reads as 0), so an
/// exponent above a double's 308 is refused too.
inline bool decimal_number(const std::string& word) {
  std::size_t at = 0;
  const auto digits = [&] {
    const std::size_t from = at;
    while (at < word.size() && digit(word[at])) ++at;
    return at - from;
  };
  if (at < word.size() && (word[at] == '+' || word[at] == '-')) ++at;
  std::size_t written = digits();
  if (at < word.size() && word[at] == '.') ++at, written += digits();
  if (written == 0) return false;
  if (at < word.size() && (word[at] == 'e' || word[at] == 'E')) {
    ++at;
    const bool negative = at < word.size() && word[at] == '-';
    if (at < word.size() && (word[at] == '+' || word[at] == '-')) ++at;
    long exponent = 0;
    const std::size_t from = at;
    for (; at < word.size() && digit(word[at]); ++at) exponent = std::min(10 * exponent + (word[at] - '0'), 100000L);
    if (at == from || (!negative && exponent > 308)) return false;
  }
  return at == word.size();
}

}  // namespace caustic::detail
