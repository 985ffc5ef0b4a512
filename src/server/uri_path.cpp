// SPDX-License-Identifier: LGPL-2.1-or-later
#include "uri_path.hpp"

#include "ascii.hpp"

#include <glib.h>

#include <algorithm>
#include <vector>

namespace caustic::server {
namespace {

// RFC 3986 5.2.4 on an absolute path: what comes after a last "." or ".."
// is a directory, so it keeps its trailing "/". A literal "." only: "%2E"
// is a name here, as it is to the URI parse.
std::string without_dot_segments(std::string_view path) {
  if (path.empty() || path.front() != '/') return std::string(path);
  std::vector<std::string_view> kept;
  bool directory = false;
  for (std::size_t at = 1; at <= path.size();) {
    const std::size_t end = std::min(path.find('/', at), path.size());
    const std::string_view segment = path.substr(at, end - at);
    directory = segment == "." || segment == "..";
    if (segment == "..") {
      if (!kept.empty()) kept.pop_back();
    } else if (segment != ".") {
      kept.push_back(segment);
    }
    at = end + 1;
  }
  std::string out;
  for (const std::string_view segment : kept) out.append("/").append(segment);
  if (directory || out.empty()) out += '/';
  return out;
}

bool unreserved(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '.' ||
         c == '_' || c == '~';
}

}  // namespace

std::string routed_path(std::string_view encoded) {
  const std::string path = without_dot_segments(encoded);
  std::string out;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const int hi = path[i] == '%' && i + 2 < path.size() ? ascii_hex_value(path[i + 1]) : -1;
    const int lo = hi >= 0 ? ascii_hex_value(path[i + 2]) : -1;
    if (lo < 0) {
      out += path[i];
      continue;
    }
    const char c = static_cast<char>(hi * 16 + lo);
    if (unreserved(c)) out += c;
    else out += '%', out += g_ascii_toupper(path[i + 1]), out += g_ascii_toupper(path[i + 2]);
    i += 2;
  }
  return out;
}

}  // namespace caustic::server
