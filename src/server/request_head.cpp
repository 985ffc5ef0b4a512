// SPDX-License-Identifier: LGPL-2.1-or-later
#include "request_head.hpp"

#include "ascii.hpp"
#include "uri_path.hpp"

#include <libsoup/soup.h>

#include <algorithm>
#include <cctype>
#include <unordered_set>

#include <nlohmann/json.hpp>

namespace caustic::server {
namespace {

bool is_tchar(unsigned char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
         std::string_view("!#$%&'*+-.^_`|~").find(static_cast<char>(c)) != std::string_view::npos;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (g_ascii_tolower(a[i]) != g_ascii_tolower(b[i])) return false;
  return true;
}

std::string_view trim_ows(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// What the HTTP library would refuse later with an empty answer is refused
// here with a reason: characters outside RFC 3986's path and query sets,
// broken or NUL percent escapes, and ".." segments hidden in escapes.
const char* target_problem(std::string_view target) {
  static constexpr std::string_view allowed = "-._~!$&'()*+,;=:@/?%";
  for (unsigned char c : target)
    if (!std::isalnum(c) && allowed.find(static_cast<char>(c)) == std::string_view::npos)
      return "the request target holds a character that must be percent-encoded";
  std::string path;
  const std::string_view raw = target.substr(0, target.find('?'));
  for (std::size_t i = 0; i < target.size(); ++i) {
    if (target[i] != '%') {
      if (i < raw.size()) path += target[i];
      continue;
    }
    const int hi = i + 2 < target.size() ? ascii_hex_value(target[i + 1]) : -1;
    const int lo = hi >= 0 ? ascii_hex_value(target[i + 2]) : -1;
    if (hi < 0 || lo < 0) return "a percent sign in the request target must start an escape like %2F";
    if (hi == 0 && lo == 0) return "the request target must not encode a NUL byte";
    if (i < raw.size()) path += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  if (path.find("/../") != std::string::npos || (path.size() >= 3 && path.compare(path.size() - 3, 3, "/..") == 0))
    return "the request target must not climb with .. segments";
  return nullptr;
}

// host = name or IPv4 or [IPv6], then an optional :port. As strict as the
// library's own parse of the URL it makes of them (GUri), which answers what
// it cannot parse ("[1::2::3]", a port past 65535) with an empty 400.
bool host_ok(std::string_view value) {
  std::string_view host = value;
  if (!value.empty() && value[0] == '[') {
    const auto close = value.find(']');
    if (close == std::string_view::npos) return false;
    const std::string literal(value.substr(1, close - 1));
    for (char c : literal)
      if (ascii_hex_value(c) < 0 && c != ':' && c != '.') return false;
    if (literal.find(':') == std::string::npos || !g_hostname_is_ip_address(literal.c_str())) return false;
    host = value.substr(0, close + 1);
    value.remove_prefix(close + 1);
  } else {
    const auto colon = value.find(':');
    host = value.substr(0, colon);
    value.remove_prefix(colon == std::string_view::npos ? value.size() : colon);
    if (host.empty()) return false;
    for (unsigned char c : host)
      if (!std::isalnum(c) && c != '.' && c != '-') return false;
  }
  if (value.empty()) return true;
  if (value[0] != ':' || value.size() < 2 || value.size() > 6) return false;
  unsigned port = 0;
  for (char c : value.substr(1)) {
    if (c < '0' || c > '9') return false;
    port = port * 10 + static_cast<unsigned>(c - '0');
  }
  return port <= 65535;
}

// Whether a media type's parameters (RFC 9110 8.3.1) name one twice, names
// being case-insensitive and a quoted value's ";" no separator. The library
// keeps the first of two charsets, where a proxy in front may keep the
// last: either reading is a guess, so the request is refused.
bool repeats_a_parameter(std::string_view value) {
  // A set, not a list searched: a 16 KiB header of thousands of names
  // would otherwise cost the main loop a quadratic scan.
  std::unordered_set<std::string> names;
  std::size_t i = value.find(';');
  while (i != std::string_view::npos && i < value.size()) {
    const std::size_t start = ++i;
    bool quoted = false;
    for (; i < value.size() && (quoted || value[i] != ';'); ++i) {
      if (quoted && value[i] == '\\') ++i;
      else if (value[i] == '"') quoted = !quoted;
    }
    const std::string_view param = value.substr(start, i - start);
    std::string name(trim_ows(param.substr(0, param.find('='))));
    if (name.empty()) continue;
    for (char& c : name) c = g_ascii_tolower(c);
    if (!names.insert(std::move(name)).second) return true;
  }
  return false;
}

RequestHead refuse(unsigned status, std::string detail) {
  RequestHead head;
  head.state = RequestHead::State::refused;
  head.status = status;
  head.detail = std::move(detail);
  return head;
}

// A head over the limit: 414 when its request line alone does not fit (the
// target is what is too long, RFC 9112 3), else 431 for its fields.
RequestHead too_large(std::string_view bytes, const HeadLimits& limits) {
  const auto line_end = bytes.find("\r\n");
  if (line_end == std::string_view::npos || line_end + 2 > limits.max_head_bytes)
    return refuse(414, "the request line is longer than " + std::to_string(limits.max_head_bytes) + " bytes");
  return refuse(431, "the request head is larger than " + std::to_string(limits.max_head_bytes) + " bytes");
}

}  // namespace

RequestHead scan_request_head(std::string_view bytes, const HeadLimits& limits) {
  const auto end = bytes.find("\r\n\r\n");
  if (end == std::string_view::npos) {
    if (bytes.size() >= limits.max_head_bytes) return too_large(bytes, limits);
    // A bare LF where CRLF belongs never becomes a valid head: say so now
    // rather than when the timeout strikes.
    for (std::size_t i = 0; i < bytes.size(); ++i)
      if (bytes[i] == '\n' && (i == 0 || bytes[i - 1] != '\r')) return refuse(400, "lines must end in CRLF");
    return {};
  }
  if (end + 4 > limits.max_head_bytes) return too_large(bytes, limits);
  const std::string_view head = bytes.substr(0, end + 2);  // every line with its CRLF
  std::size_t pos = head.find("\r\n");
  const std::string_view line = head.substr(0, pos);
  pos += 2;

  // request-line = method SP request-target SP HTTP-version
  const auto sp1 = line.find(' ');
  const auto sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp1 == std::string_view::npos || sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos)
    return refuse(400, "the request line must be: method, target and version, separated by single spaces");
  const std::string_view method = line.substr(0, sp1), version = line.substr(sp2 + 1);
  std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  if (method.empty() || method.size() > 32) return refuse(400, "the method must be 1 to 32 token characters");
  for (unsigned char c : method)
    if (!is_tchar(c)) return refuse(400, "the method must be 1 to 32 token characters");
  // A server must take the absolute form too (RFC 9112 3.2.2), which a
  // client sends to what it takes for a proxy: its authority, then the
  // path that is judged as any other. Only http: the library refuses an
  // https URI on a plain connection with an empty 400.
  constexpr std::string_view kScheme = "http://";
  if (target.size() > kScheme.size() && iequals(target.substr(0, kScheme.size()), kScheme)) {
    const std::string_view rest = target.substr(kScheme.size());
    const auto slash = rest.find('/');
    if (slash == std::string_view::npos || !host_ok(rest.substr(0, slash)))
      return refuse(400, "an absolute request target must be http://, a host name or address, and a path");
    target = rest.substr(slash);
  }
  if (target.empty() || target[0] != '/')
    return refuse(400, "the request target must be a path starting with /, or an absolute http URI");
  if (const char* why = target_problem(target)) return refuse(400, why);
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return refuse(400, "only HTTP/1.0 and HTTP/1.1 are served");
  // CONNECT takes an authority, not a path; this server is no proxy.
  if (method == "CONNECT") return refuse(400, "CONNECT is not served here");

  RequestHead out;
  std::size_t headers = 0, hosts = 0, lengths = 0, types = 0, authorizations = 0;
  bool chunked_or_other = false, upgrade_ws = false;
  while (pos < head.size()) {
    const auto eol = head.find("\r\n", pos);
    const std::string_view field = head.substr(pos, eol - pos);
    pos = eol + 2;
    if (++headers > limits.max_headers)
      return refuse(431, "more than " + std::to_string(limits.max_headers) + " header fields");
    if (field.empty() || field[0] == ' ' || field[0] == '\t')
      return refuse(400, "folded or empty header lines are not allowed");
    const auto colon = field.find(':');
    if (colon == std::string_view::npos || colon == 0) return refuse(400, "a header field needs a name and a colon");
    const std::string_view name = field.substr(0, colon);
    for (unsigned char c : name)
      if (!is_tchar(c)) return refuse(400, "a header name must be token characters");
    const std::string_view value = trim_ows(field.substr(colon + 1));
    for (unsigned char c : value)
      if ((c < 0x20 && c != '\t') || c == 0x7f) return refuse(400, "a header value must not hold control characters");
    if (iequals(name, "Host")) {
      ++hosts;
      if (!host_ok(value)) return refuse(400, "the Host header must be a host name or address and an optional port");
    } else if (iequals(name, "Content-Length")) {
      ++lengths;
      if (value.empty() || value.size() > 18) return refuse(400, "Content-Length must be 1 to 18 decimal digits");
      std::uint64_t n = 0;
      for (unsigned char c : value) {
        if (c < '0' || c > '9') return refuse(400, "Content-Length must be 1 to 18 decimal digits");
        n = n * 10 + (c - '0');
      }
      out.content_length = n;
    } else if (iequals(name, "Content-Type")) {
      ++types;
      if (repeats_a_parameter(value)) return refuse(400, "the Content-Type header gives one of its parameters twice");
    } else if (iequals(name, "Authorization")) {
      ++authorizations;
    } else if (iequals(name, "Transfer-Encoding")) {
      chunked_or_other = true;
    } else if (iequals(name, "Upgrade")) {
      upgrade_ws = iequals(value, "websocket");
    } else if (iequals(name, "Expect") && !iequals(value, "100-continue")) {
      // The library answers any other expectation with an empty 417.
      return refuse(417, "the only expectation served is 100-continue");
    } else if (iequals(name, "Expect") && version == "HTTP/1.0") {
      out.ignored_expects.push_back(static_cast<std::size_t>(field.data() - bytes.data()));
    }
  }
  if (lengths > 1) return refuse(400, "more than one Content-Length header");
  // Fields of one value each: the library reads the last of two, where a
  // proxy in front may have judged the first.
  if (types > 1) return refuse(400, "more than one Content-Type header");
  if (authorizations > 1) return refuse(400, "more than one Authorization header");
  if (chunked_or_other && lengths) return refuse(400, "Content-Length and Transfer-Encoding together");
  if (chunked_or_other) return refuse(411, "request bodies need a Content-Length (no Transfer-Encoding)");
  if (hosts > 1 || (hosts == 0 && version == "HTTP/1.1")) return refuse(400, "HTTP/1.1 requests need one Host header");
  const std::string routed = routed_path(target.substr(0, target.find('?')));
  const bool upload = method == "POST" && std::find(limits.upload_paths.begin(), limits.upload_paths.end(),
                                                    routed) != limits.upload_paths.end();
  const std::size_t max_body = upload ? limits.max_upload_bytes : limits.max_body_bytes;
  if (out.content_length > max_body)
    return refuse(413, "the body is larger than " + std::to_string(max_body) + " bytes");
  out.state = RequestHead::State::complete;
  out.head_bytes = end + 4;
  // Only what can become a signalling socket is let go of the connection's
  // timeouts (the session watches its viewer instead): any other request
  // with an Upgrade header, or one with a body, would hold a connection
  // for good. A refused handshake closes its connection (http_api.cpp).
  const std::string_view path = target.substr(0, target.find('?'));
  constexpr std::string_view kSignal = "/signal";
  out.websocket = upgrade_ws && method == "GET" && out.content_length == 0 && path.size() >= kSignal.size() &&
                  path.substr(path.size() - kSignal.size()) == kSignal;
  return out;
}

const char* status_phrase(unsigned status) {
  // A problem's title is the status's phrase (RFC 9457 4.2.1): RFC 9110's,
  // where libsoup has none or RFC 7231's.
  switch (status) {
    case 413: return "Content Too Large";                  // RFC 9110
    case 414: return "URI Too Long";                       // RFC 9110
    case 421: return "Misdirected Request";                // RFC 9110
    case 422: return "Unprocessable Content";              // RFC 9110
    case 429: return "Too Many Requests";                  // RFC 6585
    case 431: return "Request Header Fields Too Large";    // RFC 6585
    default: return soup_status_get_phrase(status);
  }
}

std::string canned_problem(unsigned status, const std::string& detail, const std::string& extra_headers) {
  const char* phrase = status_phrase(status);
  const std::string body = nlohmann::json{{"type", "about:blank"},
                                          {"title", phrase ? phrase : "Error"},
                                          {"status", status},
                                          {"detail", detail}}
                               .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return "HTTP/1.1 " + std::to_string(status) + " " + (phrase ? phrase : "Error") +
         "\r\nContent-Type: application/problem+json\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY"
         "\r\nReferrer-Policy: no-referrer\r\nContent-Security-Policy: default-src 'none'"
         "\r\nAccept-Ranges: none\r\nConnection: close\r\n" +  // as every other answer (http_api.cpp)
         extra_headers +
         "\r\n" + body;
}

bool WebSocketGuard::header_done() {
  const bool masked = header_[1] & 0x80;
  const unsigned len7 = header_[1] & 0x7f;
  const std::size_t need = 2 + (len7 == 126 ? 2 : len7 == 127 ? 8 : 0) + (masked ? 4 : 0);
  if (header_have_ < need) {
    header_need_ = need;
    return false;
  }
  std::uint64_t length = len7;
  if (len7 == 126) length = (std::uint64_t(header_[2]) << 8) | header_[3];
  if (len7 == 127) {
    length = 0;
    for (int i = 0; i < 8; ++i) length = (length << 8) | header_[2 + i];
  }
  const unsigned opcode = header_[0] & 0x0f;
  const bool fin = header_[0] & 0x80;
  ++frames_;
  if (opcode >= 8) {
    if (length > 125 || !fin) {
      error_ = "a WebSocket control frame must be whole and at most 125 bytes";
      close_code_ = 1002;  // protocol error (RFC 6455 7.4.1)
    }
  } else {
    if (length > max_frame_) error_ = "a WebSocket frame is larger than " + std::to_string(max_frame_) + " bytes";
    if (opcode != 0) message_bytes_ = 0;  // a new message starts
    message_bytes_ += length;
    if (message_bytes_ > max_message_)
      error_ = "a WebSocket message is larger than " + std::to_string(max_message_) + " bytes";
    if (fin) message_bytes_ = 0;
  }
  payload_left_ = length;
  in_payload_ = true;
  header_have_ = 0;
  header_need_ = 2;
  return true;
}

bool WebSocketGuard::feed(const unsigned char* data, std::size_t size) {
  std::size_t i = 0;
  while (error_.empty() && i < size) {
    if (in_payload_) {
      const std::uint64_t take = std::min<std::uint64_t>(payload_left_, size - i);
      i += take;
      payload_left_ -= take;
      if (payload_left_ == 0) in_payload_ = false;
      continue;
    }
    header_[header_have_++] = data[i++];
    if (header_have_ >= header_need_ && header_done() && payload_left_ == 0) in_payload_ = false;
  }
  return error_.empty();
}

}  // namespace caustic::server
