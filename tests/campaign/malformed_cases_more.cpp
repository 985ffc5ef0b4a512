// SPDX-License-Identifier: LGPL-2.1-or-later
// The content faults: bodies, tokens, parameter values, static paths and
// WebSocket handshakes.
#include "case_rules.hpp"

#include "../ws_client.hpp"

namespace campaign {

using namespace cases;
using caustic::testing::kWsUpgrade;
using caustic::testing::kWsVersion;
using caustic::testing::ws_key_field;
using caustic::testing::ws_upgrade_request;

Case CaseGenerator::body_case() {
  const std::string scene = victim_.scene;
  std::string nested = std::string(60000, '[') + std::string(60000, ']');
  std::string deep_object;
  for (int i = 0; i < 20000; ++i) deep_object += "{\"a\":";
  deep_object.append("1").append(20000, '}');
  const std::string nul_patch = valid_patch() + std::string("\0junk", 5);
  std::vector<std::pair<std::string, std::string>> bodies = {
      {"{\"scene\":\"" + scene + std::string("\"}\0junk", 7), "application/json"},
      {"{\"scene\":\"" + scene + std::string("\0\"}", 3), "application/json"},
      {"{\"scene\":\"\xff\xfe\"}", "application/json"},
      {"{\"scene\":\"\xc3\x28\"}", "application/json"},
      {"{\"scene\":\"\\ud800\"}", "application/json"},
      {nested, "application/json"},
      {deep_object, "application/json"},
      {"[]", "application/json"},
      {"null", "application/json"},
      {"", "application/json"},
      {"{\"scene\":1}", "application/json"},
      {"{\"scene\":\"nope\"}", "application/json"},
      {"{\"scene\":\"" + scene + "\",\"codec\":\"av1\"}", "application/json"},
      {"{\"scene\":\"" + scene + "\",\"extra\":1}", "application/json"},
      {"{\"scene\":\"" + scene + "\"}", "text/plain"},
      {"{\"scene\":\"" + scene + "\"}", ""},
      {"{\"scene\":\"" + scene + "\"}", "application/merge-patch+json"},
      {"{\"scene\":\"" + scene + "\"}", "application/jsonx"},
      {"{\"scene\":\"" + std::string((1 << 20) + 10, 'x') + "\"}", "application/json"},
      {"{\"scene\":\"" + scene + "\",\"scene\":1}", "application/json"}};
  Case c;
  if (rng_() % 3 == 0) {
    // The contract's named case: a valid PATCH with bytes after a NUL.
    c = patch(nul_patch);
    c.rule = status_in("a valid PATCH followed by NUL and junk is refused with 400", {400});
    c.state = 2;
    return c;
  }
  if (rng_() % 4 == 0) {
    c = patch(rng_() % 2 ? nested : deep_object);
    c.rule = status_in("deeply nested JSON is refused with 400 or 413", {400, 413});
    return c;
  }
  const auto& [body, type] = bodies[rng_() % bodies.size()];
  Headers h;
  if (!type.empty()) h.emplace_back("Content-Type", type);
  c.bytes = make_request("POST", "/api/v1/sessions", h, body);
  c.state = 1;
  c.rule = refused("a malformed session request creates nothing");
  return c;
}

Case CaseGenerator::auth_case() {
  const std::string params = "/api/v1/sessions/" + victim_.id + "/params";
  const std::string other = "/api/v1/sessions/" + random_id() + "/params";
  std::string wrong = victim_.token;
  wrong[rng_() % wrong.size()] ^= 1;
  Case c;
  c.state = 1;
  switch (rng_() % 12) {
    case 0:
      c.bytes = make_request("GET", params, {{"Authorization", "Bearer " + wrong}});
      break;
    case 1:
      c.bytes = make_request("GET", params);
      break;
    case 2:
      c.bytes = make_request("GET", params, {{"Authorization", "Bearer"}});
      break;
    case 3:
      c.bytes = make_request("GET", params, {{"Authorization", "Basic " + victim_.token}});
      break;
    case 4:
      c.bytes = make_request("GET", other, {{"Authorization", "Bearer " + victim_.token}});
      break;
    case 5:
      c.bytes = make_request("DELETE", "/api/v1/sessions/" + victim_.id, {{"Authorization", "Bearer " + wrong}});
      break;
    case 6:
      c.bytes =
          make_request("PATCH", params,
                       {{"Authorization", "Bearer " + victim_.token.substr(1)}, {"Content-Type", "application/json"}},
                       valid_patch());
      break;
    case 7:
      c.bytes =
          make_request("DELETE", "/api/v1/sessions/" + random_id(), {{"Authorization", "Bearer " + victim_.token}});
      break;
    case 8:
      c.bytes = make_request("GET", params, {{"Authorization", "Bearer " + victim_.token + "x"}});
      break;
    case 9:
      c.bytes = make_request("GET", params, {{"Authorization", "Bearer  " + wrong + " "}});
      break;
    case 10:
      c.bytes = make_request("PATCH", other,
                             {{"Authorization", "Bearer " + victim_.token}, {"Content-Type", "application/json"}},
                             valid_patch());
      break;
    default: {
      // The scheme is case-insensitive (RFC 9110): a lower-case one works.
      c.bytes =
          make_request("GET", params, {{"Authorization", pick({"bearer ", "BEARER ", "BeArEr "}) + victim_.token}});
      c.rule = status_in("the Bearer scheme is case-insensitive", {200});
      return c;
    }
  }
  c.rule = status_in("a wrong token or unknown session answers 401", {401});
  return c;
}

Case CaseGenerator::patch_value_case() {
  const int which = static_cast<int>(rng_() % 10);
  if (which == 0) {
    static const char* fixed[] = {"{\"mesh\":\"x\"}",
                                  "{\"name\":\"x\"}",
                                  "{\"description\":\"x\"}",
                                  "{\"render\":{\"width\":512}}",
                                  "{\"render\":{\"height\":512}}",
                                  "{\"object\":{\"flat_face_normal\":[1,0,0]}}"};
    Case c = patch(fixed[rng_() % std::size(fixed)]);
    c.rule = status_in("fixed keys are refused with 422", {422});
    c.state = 2;
    return c;
  }
  if (which == 1) {
    Case c = patch(
        pick({"{\"nonexistent\":1}", "{\"render\":{\"nonexistent\":1}}", "{\"\":1}", "{\"light\":{\"\\u0000\":1}}"}));
    c.rule = status_in("unknown keys are refused with 422", {422});
    c.state = 2;
    return c;
  }
  if (leaves_.empty()) return patch("{\"x\":");
  const auto& [path, value] = leaves_[rng_() % leaves_.size()];
  // Literals that are not JSON, or numbers no double holds: 400.
  if (which == 2) {
    Case c = patch(
        nest(path, pick({"NaN", "Infinity", "-Infinity", "1e999", "-1e400", "nan", "0x10", "01", "1.", ".5", "+1"})));
    c.rule = status_in("NaN, infinities and overflowing numbers are refused with 400", {400});
    c.state = 2;
    return c;
  }
  std::vector<std::string> bad;
  if (value.is_number())
    bad = {"\"NaN\"",  "\"1\"", "true", "[1]", "{}", "\"\"", "1e308", "-1e308", "123456789012345678901234567890",
           "4.9e-324", "-0"};
  else if (value.is_string())
    bad = {"12",
           "true",
           "[]",
           "{}",
           "\"\xff\xfe\"",
           "\"" + std::string(100000, 'z') + "\"",
           "\"../../etc/passwd\"",
           "\"\\u0000\""};
  else if (value.is_boolean())
    bad = {"\"true\"", "1", "0", "\"yes\"", "[]"};
  else if (value.is_array())
    bad = {"\"x\"", "[]", "[1,2,3,4,5,6,7,8,9,10,11]", "[\"a\",\"b\"]", "[[[]]]", "[1e999]", "{}"};
  else
    bad = {"1", "\"x\"", "[]"};
  Case c = patch(nest(path, pick(bad)), rng_() % 2 ? "application/merge-patch+json" : "application/json");
  return c;
}

Case CaseGenerator::static_case() {
  Case c;
  if (rng_() % 4 == 0) {
    // Odd but harmless spellings of files that exist: any non-5xx answer.
    c.bytes = make_request("GET", pick({"/index.html/", "/%2F", "/js/", "/index.html?x=%00", "/index.html#x",
                                        "/viewer.html?token=%ff%fe", "/css//", "/%69ndex.html"}));
    return c;
  }
  const std::string path = pick({"/../../../../etc/passwd",
                                 "/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
                                 "/..%2f..%2f..%2fetc%2fpasswd",
                                 "/%252e%252e/%252e%252e/etc/passwd",
                                 "/js/../../CMakeLists.txt",
                                 "/.git/config",
                                 "/.hidden",
                                 "//etc/passwd",
                                 "/index.html%00.png",
                                 "/%c0%ae%c0%ae/%c0%ae%c0%ae/etc/passwd",
                                 "/..\\..\\etc\\passwd",
                                 "/css/%2e%2e/%2e%2e/package.json",
                                 "/package.json",
                                 "/package-lock.json",
                                 "/./package.json",
                                 "/%70ackage.json",
                                 "/PACKAGE.JSON",
                                 "/%",
                                 "/%zz",
                                 "/..;/etc/passwd",
                                 "/js/.eslintrc",
                                 "/.env",
                                 "/proc/self/environ",
                                 std::string("/").append(5000, '%').append("41")});
  c.bytes = make_request(rng_() % 5 ? "GET" : "HEAD", path);
  c.head = c.bytes.rfind("HEAD", 0) == 0;
  c.rule = [](KindReport& rep, const Response& r, const std::string& s) {
    rep.check("paths outside web/, hidden and package files answer 404 or 400",
              r.kind != Response::Answer || r.status == 404 || r.status == 400, s);
  };
  return c;
}

Case CaseGenerator::handshake_case() {
  const std::string good = "/api/v1/sessions/" + victim_.id + "/signal?token=" + victim_.token;
  std::string wrong = victim_.token;
  wrong[0] = wrong[0] == 'a' ? 'b' : 'a';
  const std::string& up = kWsUpgrade;
  const std::string& v13 = kWsVersion;
  const std::string session = "/api/v1/sessions/" + victim_.id + "/signal";
  std::vector<std::string> requests = {
      make_request("GET", good),             // not a WebSocket at all
      request_text("GET", good, up + v13),  // no key
      request_text("GET", good, up + ws_key_field("short") + v13),
      request_text("GET", good, up + ws_key_field() + "Sec-WebSocket-Version: 8\r\n"),
      request_text("GET", good, "Upgrade: h2c\r\nConnection: Upgrade\r\n"),
      request_text("POST", good, up + ws_key_field() + v13 + "Content-Length: 0\r\n"),
      ws_upgrade_request(session + "?token=" + wrong),
      ws_upgrade_request("/api/v1/sessions/" + random_id() + "/signal?token=" + victim_.token),
      ws_upgrade_request(session),  // no token
      ws_upgrade_request("/api/v1/health"),
      request_text("GET", good + "&token=" + wrong, up + v13)};
  Case c;
  c.bytes = pick(requests);
  c.state = 2;
  c.rule = [](KindReport& rep, const Response& r, const std::string& s) {
    rep.check("a bad WebSocket handshake is refused (never 101)", !(r.kind == Response::Answer && r.status == 101), s);
  };
  return c;
}

}  // namespace campaign
