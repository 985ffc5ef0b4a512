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
/// negative one counts back from the last vertex) within an int. `index`
/// gets v, vt and vn as written, 0 for one left out.
inline bool face_corner(const std::string& word, long long index[3]) {
  std::size_t at = 0;
  index[0] = index[1] = index[2] = 0;
  for (int part = 0; part < 3; ++part) {
    if (part > 0) {
      if (at == word.size()) return true;
      if (word[at] != '/') return false;
      ++at;
      if (part == 1 && at < word.size() && word[at] == '/') continue;  // v//vn
    }
    const bool negative = at < word.size() && word[at] == '-';
    if (negative) ++at;
    const std::size_t digits = at;
    long long value = 0;  // at most 10 digits: no overflow
    for (; at < word.size() && digit(word[at]) && at - digits < 11; ++at) value = 10 * value + (word[at] - '0');
    if (at == digits || at - digits > 10 || value == 0 || value > 2147483647LL) return false;
    index[part] = negative ? -value : value;
  }
  return at == word.size();
}

/// What a face's corners name, checked against what the file holds: a
/// negative index counts back from the last one read so far (past the
/// first: an error at its line), a positive one names one the whole file
/// must hold (the largest is checked at the end, with its line).
struct Named {
  std::size_t largest = 0, line = 0;  // the largest positive index, and where
  // An error, or "": `index` (nonzero) at line `number`, `so_far` read.
  std::string take(long long index, std::size_t so_far, std::size_t number, const char* what) {
    if (index < 0 && static_cast<unsigned long long>(-index) > so_far)
      return "a face's corner names " + std::string(what) + " " + std::to_string(index) +
             ", which does not exist (counted back from the last: " + std::to_string(so_far) + " so far)";
    if (index > 0 && static_cast<std::size_t>(index) > largest) {
      largest = static_cast<std::size_t>(index);
      line = number;
    }
    return "";
  }
  // An error for the largest, or "": `total` in the file.
  std::string past(std::size_t total, const char* what) const {
    if (largest <= total) return "";
    return "a face's corner names " + std::string(what) + " " + std::to_string(largest) +
           ", which does not exist (the file holds " + std::to_string(total) + ")";
  }
};

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
