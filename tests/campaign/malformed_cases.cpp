// SPDX-License-Identifier: LGPL-2.1-or-later
// The generator's core and the framing faults: methods, request lines,
// headers and body lengths.
#include "case_rules.hpp"

namespace campaign {

using namespace cases;

CaseGenerator::CaseGenerator(unsigned seed, Victim victim) : rng_(seed) { set_victim(std::move(victim)); }

void CaseGenerator::set_victim(Victim v) {
  victim_ = std::move(v);
  leaves_.clear();
  std::vector<std::string> path;
  collect(victim_.params, path, leaves_);
  // The contract fixes these; they have cases of their own.
  std::erase_if(leaves_, [](const auto& l) {
    const auto& p = l.first;
    return p[0] == "name" || p[0] == "description" || p[0] == "mesh" ||
           (p[0] == "render" && p.size() > 1 && (p[1] == "width" || p[1] == "height"));
  });
}

std::string CaseGenerator::pick(const std::vector<std::string>& v) { return v[rng_() % v.size()]; }

std::string CaseGenerator::random_id() {
  std::string id;
  for (int i = 0; i < 32; ++i) id += "0123456789abcdef"[rng_() % 16];
  return id;
}

std::string CaseGenerator::endpoint() {
  const std::string s = "/api/v1/sessions/" + (rng_() % 4 ? victim_.id : random_id());
  return pick({"/api/v1/health", "/api/v1/scenes", "/api/v1/scenes/" + victim_.scene + "/thumbnail.png",
               "/api/v1/scenes/nope/thumbnail.png", "/api/v1/sessions", s, s + "/params",
               s + "/signal?token=" + victim_.token, "/metrics", "/", "/index.html", "/viewer.html", "/nope",
               "/api/v1/nope", "/api/v2/health", "/api/v1/sessions/" + victim_.id + "/params/extra",
               "/api/v1/designs", "/api/v1/designs?name=x", "/api/v1/designs/" + random_id(),
               "/api/v1/scenes/" + victim_.scene, "/api/v1/scenes/nope"});
}

// A merge patch that sets a leaf to the value it has: valid, so only the
// framing around it can make it wrong.
std::string CaseGenerator::valid_patch() {
  for (const auto& [path, value] : leaves_)
    if (value.is_number()) return nest(path, value.dump());
  return "{}";
}

Case CaseGenerator::patch(const std::string& body, const std::string& type) {
  Case c;
  c.bytes = make_request("PATCH", "/api/v1/sessions/" + victim_.id + "/params",
                         {{"Authorization", "Bearer " + victim_.token}, {"Content-Type", type}}, body);
  c.state = 1;
  return c;
}

Case CaseGenerator::next() {
  using Gen = Case (CaseGenerator::*)();
  static const Gen gens[] = {
      &CaseGenerator::method_case,      &CaseGenerator::request_line_case, &CaseGenerator::header_case,
      &CaseGenerator::length_case,      &CaseGenerator::body_case,         &CaseGenerator::auth_case,
      &CaseGenerator::patch_value_case, &CaseGenerator::static_case,       &CaseGenerator::handshake_case};
  static const char* names[] = {"method", "request-line", "headers", "content-length", "body",
                                "auth",   "patch-values", "static",  "ws-handshake"};
  const size_t i = counter_++ % std::size(gens);
  Case c = (this->*gens[i])();
  c.category = names[i];
  return c;
}

Case CaseGenerator::method_case() {
  std::string method =
      pick({"GET", "HEAD",  "POST",     "PATCH",   "DELETE", "PUT", "OPTIONS", "TRACE", "CONNECT",  "PROPFIND",
            "get", "Patch", "\xff\xfe", "GE\xe9T", "G\tT",   "",    "GET GET", "-",     "M-SEARCH", "BREW"});
  if (rng_() % 10 == 0) method = std::string(100 + rng_() % 20000, 'A' + static_cast<char>(rng_() % 26));
  Case c;
  const std::string target = endpoint();
  // Never the victim's token here: a DELETE that works would end it.
  Headers headers = {{"Content-Type", "application/json"}};
  const std::string body = rng_() % 2 ? "{}" : "";
  c.bytes = make_request(method, target, headers, body);
  c.head = method == "HEAD";
  // Longer than the 32 characters any method needs: refused at the head
  // (400) before a route or a token is looked at, whatever the target.
  c.broken = method.empty() || method.find_first_of(" \t\xff\xfe\xe9") != std::string::npos || method.size() > 32;
  c.state = (target.find(victim_.id) != std::string::npos || method != "GET") ? 1 : 0;
  // CONNECT takes an authority, not a path: a 400 for it is right.
  const bool session_route = target.find("/api/v1/sessions/" + victim_.id) == 0 &&
                             target.find("/signal") == std::string::npos && target.find("/extra") == std::string::npos;
  if (!c.broken && method != "CONNECT" && session_route)
    c.rule = status_in("session endpoints without a token answer 401 or 405", {401, 405});
  return c;
}

Case CaseGenerator::request_line_case() {
  const std::string t = endpoint();
  std::vector<std::string> lines = {
      "GET\r\n\r\n",
      "GET " + t + "\r\n\r\n",
      "GET " + t + " HTTP/9.9\r\nHost: x\r\n\r\n",
      "GET " + t + " HTTP/1.1 extra\r\nHost: x\r\n\r\n",
      "GET  " + t + "  HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET http://example.invalid" + t + " HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET * HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET /%00 HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET " + t + " HTTP/1.1\nHost: x\n\n",
      "GET /\x01\x02 HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET " + t + " HTTP/1.1\r\r\r\r",
      "GET /" + std::string(100000 + rng_() % 100000, 'a') + " HTTP/1.1\r\nHost: x\r\n\r\n",
      "HTTP/1.1 200 OK\r\n\r\n",
      "\r\n\r\n\r\nGET / HTTP/1.1\r\nHost: x\r\n\r\n",
      "\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03",
      "GET " + t + " HTTP/1.1\r\nHost: x\r\n",
      "GET " + t + " HTTP/1\r\nHost: x\r\n\r\n",
      "GET " + t + " HTTP/1.10\r\nHost: x\r\n\r\n",
      "GET " + t + " http/1.1\r\nHost: x\r\n\r\n",
      "GET " + t + " HTTP/0.9\r\n\r\n",
      "GET #frag HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET ?x=1 HTTP/1.1\r\nHost: x\r\n\r\n"};
  Case c;
  c.bytes = pick(lines);
  if (rng_() % 8 == 0) {
    c.bytes.clear();
    for (int i = 0, n = 1 + static_cast<int>(rng_() % 400); i < n; ++i) c.bytes += static_cast<char>(rng_());
  }
  c.broken = true;
  c.half_close = true;  // an unfinished line must not keep us for header_timeout_s
  c.state = c.bytes.find(victim_.id) != std::string::npos ? 1 : 0;
  return c;
}

Case CaseGenerator::header_case() {
  const std::string t = endpoint();
  const std::string line = "GET " + t + " HTTP/1.1\r\n";
  std::string h;
  switch (rng_() % 12) {
    case 0:
      for (int i = 0, n = 100 + static_cast<int>(rng_() % 20000); i < n; ++i)
        h += "X-Fill-" + std::to_string(i) + ": v\r\n";
      break;
    case 1:
      h = "X-Big: " + std::string(8192 + rng_() % (1 << 20), 'a') + "\r\n";
      break;
    case 2:
      h = "NoColonHere\r\n";
      break;
    case 3:
      h = "Bad Name: x\r\n";
      break;
    case 4:
      h = "X-A: a\r\n  folded continuation\r\n";
      break;
    case 5:
      h = std::string("X-Nul: a\0b\r\n", 12);
      break;
    case 6:
      h = "";
      break;  // no Host at all
    case 7:
      h = "Host: a\r\nHost: b\r\n";
      break;
    case 8:
      h = "X-Bytes: \xff\xfe\xc3\x28\r\n";
      break;
    case 9:
      h = ": empty-name\r\n";
      break;
    case 10:
      h = "X-A\t: tab-before-colon\r\n";
      break;
    default:
      h = std::string(2000 + rng_() % 50000, 'H') + ": x\r\n";
      break;
  }
  Case c;
  const bool host = h.find("Host:") == std::string::npos && rng_() % 12 != 0;
  c.bytes = line + (host ? "Host: 127.0.0.1\r\n" : "") + h + "Connection: close\r\n\r\n";
  c.broken = true;
  c.state = t.find(victim_.id) != std::string::npos ? 1 : 0;
  return c;
}

Case CaseGenerator::length_case() {
  const bool on_patch = rng_() % 2;
  const std::string body = on_patch ? valid_patch() : nlohmann::json{{"scene", victim_.scene}}.dump();
  const std::string target = on_patch ? "/api/v1/sessions/" + victim_.id + "/params" : "/api/v1/sessions";
  const std::string fields =
      (on_patch ? "Authorization: Bearer " + victim_.token + "\r\nContent-Type: application/merge-patch+json\r\n"
                : "Content-Type: application/json\r\n") +
      "Connection: close\r\n";
  const std::string n = std::to_string(body.size());
  auto hex = [](size_t v) {
    char b[32];
    std::snprintf(b, sizeof b, "%zx", v);
    return std::string(b);
  };
  const std::string chunked = hex(body.size()) + "\r\n" + body + "\r\n0\r\n\r\n";
  std::vector<std::pair<std::string, std::string>> variants = {
      {"Content-Length: " + n + "\r\nContent-Length: " + std::to_string(body.size() + 3) + "\r\n", body + "abc"},
      {"Content-Length: -" + n + "\r\n", body},
      {"Content-Length: +" + n + "\r\n", body},
      {"Content-Length: 0x" + hex(body.size()) + "\r\n", body},
      {"Content-Length: 99999999999999999999999999\r\n", body},
      {"Content-Length: " + n + ", " + n + "\r\n", body},
      {"Content-Length: \r\n", body},
      {"Content-Length: abc\r\n", body},
      {"Content-Length: " + n + "\r\nTransfer-Encoding: chunked\r\n", chunked},
      {"Transfer-Encoding: chunked\r\nContent-Length: 3\r\n", chunked},
      {"Transfer-Encoding: chunked\r\n", "zz\r\n" + body + "\r\n0\r\n\r\n"},
      {"Transfer-Encoding: chunked\r\n", "-1\r\n" + body + "\r\n0\r\n\r\n"},
      {"Transfer-Encoding: chunked\r\n", "ffffffffffffffffffff\r\n" + body + "\r\n0\r\n\r\n"},
      {"Transfer-Encoding: chunked\r\n", hex(body.size()) + "\r\n" + body + "XX0\r\n\r\n"},
      {"Transfer-Encoding: chunked\r\n", hex(body.size()) + ";ext=\x01\r\n" + body + "\r\n0\r\n\r\n"},
      {"Transfer-Encoding: chunked\r\n", hex(body.size()) + "\r\n" + body + "\r\n"},
      {"Transfer-Encoding: chunked\r\n", hex(body.size() + 50) + "\r\n" + body},
      {"Transfer-Encoding: gzip\r\n", body},
      {"Transfer-Encoding: chunked, chunked\r\n", chunked},
      {"Transfer-Encoding: identity\r\nContent-Length: " + n + "\r\n", body},
      {"Content-Length: " + std::to_string(body.size() + 100) + "\r\n", body},
      {"Expect: 100-continue\r\nContent-Length: 999999999\r\n", ""}};
  const auto& [headers, payload] = variants[rng_() % variants.size()];
  Case c;
  // The framing under test is written out, so no length is added for the body.
  c.bytes = request_text(on_patch ? "PATCH" : "POST", target, fields + headers) + payload;
  c.broken = true;
  c.half_close = true;
  // Whatever framing the server settles on, a POST that creates a session
  // or a PATCH that lands would be an ambiguity an attacker can use.
  c.state = 1;
  if (headers.find("99999999999999999999999999") != std::string::npos ||
      headers.find("999999999\r") != std::string::npos)
    c.rule = refused("a huge Content-Length is refused");
  return c;
}

}  // namespace campaign
