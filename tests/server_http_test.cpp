// SPDX-License-Identifier: LGPL-2.1-or-later
// HTTP's own rules as the API and the file server keep them, written byte
// for byte: how a path's escapes are read, which request targets are taken.
#include "raw_http.hpp"
#include "rest_fixture.hpp"
#include "server_process.hpp"
#include "web_folder.hpp"

using caustic::testing::raw_body;
using caustic::testing::raw_header;
using caustic::testing::raw_request;
using caustic::testing::raw_status;
using caustic::testing::Rest;
using caustic::testing::ServerProcess;
using caustic::testing::WebFolder;

namespace {

std::string authorization(const nlohmann::json& session) {
  return "Authorization: Bearer " + session["token"].get<std::string>() + "\r\n";
}

std::string params_path(const nlohmann::json& session) {
  return "/api/v1/sessions/" + session["id"].get<std::string>() + "/params";
}

}  // namespace

// An escape names a character within its segment (RFC 3986 2.2): "%2F" is
// no separator, and "%25" is a percent sign, decoded once. An escaped
// unreserved character is that character (6.2.2.2).
TEST(HttpPaths, EscapesAreDecodedOnceAndAnEncodedSlashSeparatesNothing) {
  const WebFolder web({{"index.html", "<!doctype html><title>ok</title>"}, {"sub/app.js", "console.log(1);"}});
  ServerProcess server({"--web-dir", web.dir()});
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/sub/app.js")), 200);
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/s%75b/app%2Ejs")), 200);
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/api/v1/scenes/l%65ns")), 200);
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/api/v1/%68ealth")), 200);
  for (const char* target : {"/sub%2Fapp.js", "/sub%2fapp.js", "/index%252ehtml", "/sub%252Fapp.js",
                             "/api/v1/scenes%2Flens", "/api/v1/scenes/lens%2Fthumbnail.png", "/api%2Fv1%2Fhealth"})
    EXPECT_EQ(raw_status(raw_request(server.port(), "GET", target)), 404) << target;
}

// A server must take the absolute form of a request target (RFC 9112
// 3.2.2); its path is judged as any other.
TEST(HttpTargets, TheAbsoluteFormIsServedAsItsPath) {
  ServerProcess server;
  const std::string authority = "127.0.0.1:" + std::to_string(server.port());
  const std::string health = raw_request(server.port(), "GET", "http://" + authority + "/api/v1/health");
  EXPECT_EQ(raw_status(health), 200) << health;
  EXPECT_NE(raw_body(health).find("\"status\":\"ok\""), std::string::npos) << health;
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "HTTP://" + authority + "/api/v1/scenes/lens")), 200);
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "http://" + authority + "/api/v1/nothing")), 404);
  // Its path is held to the same rules, and it needs one.
  for (const std::string& target : {"http://" + authority + "/a/%2e%2e/index.html", "http://" + authority,
                                    "http://user@" + authority + "/api/v1/health", "ftp://" + authority + "/"}) {
    const std::string answer = raw_request(server.port(), "GET", target);
    EXPECT_EQ(raw_status(answer), 400) << target;
    EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json") << target;
  }
}

// An authority the HTTP library cannot parse (a port past 65535, a
// bracketed literal that is no IPv6 address) and an https URI on this plain
// connection got the library's own 400 with an empty body: each is a
// problem document saying why, and a port the library takes is served.
TEST(HttpTargets, AnAuthorityTheLibraryCannotTakeIsAProblem) {
  ServerProcess server;
  const std::string path = "/api/v1/health";
  for (const std::string host : {"127.0.0.1:65536", "127.0.0.1:99999", "[::1]:70000", "[]", "[1::2::3]", "[12345::]",
                                 "[::1.2.3.4.5]", "[.]"}) {
    const std::string by_header = raw_request(server.port(), "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n");
    EXPECT_EQ(raw_status(by_header), 400) << host;
    EXPECT_EQ(raw_header(by_header, "Content-Type"), "application/problem+json") << host << ": " << by_header;
    const std::string absolute = raw_request(server.port(), "GET", "http://" + host + path);
    EXPECT_EQ(raw_status(absolute), 400) << host;
    EXPECT_EQ(raw_header(absolute, "Content-Type"), "application/problem+json") << host << ": " << absolute;
  }
  for (const std::string& target : {"https://127.0.0.1" + path, "HTTPS://127.0.0.1" + path}) {
    const std::string answer = raw_request(server.port(), "GET", target);
    EXPECT_EQ(raw_status(answer), 400) << target;
    EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json") << target << ": " << answer;
  }
  for (const std::string host : {"127.0.0.1:65535", "[::1]", "[::ffff:127.0.0.1]:8080"}) {
    EXPECT_EQ(raw_status(raw_request(server.port(), "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n")), 200)
        << host;
    EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "http://" + host + path)), 200) << host;
  }
}

// An HTTP/1.0 request may leave Host out; the library then kept its whole
// target, "?" and query, as the path: /api/v1/health?x=1 was no endpoint
// (404), a static file asked with a query no file, and a session's token
// in the query went unread. Path and query are told apart as for any other.
TEST_F(Rest, AnHttp10RequestWithoutHostKeepsItsQueryApart) {
  const nlohmann::json s = create();
  const auto without_host = [&](const std::string& target) {
    return raw_request(server_.port(), "GET " + target + " HTTP/1.0\r\n\r\n");
  };
  for (const char* target : {"/api/v1/health?x=1", "/api/v1/scenes/lens?x", "/?v=2", "/index.html?v=2"})
    EXPECT_EQ(raw_status(without_host(target)), 200) << target;
  const std::string signal = without_host(s["signal_url"].get<std::string>());
  EXPECT_EQ(raw_status(signal), 400) << signal;
  EXPECT_NE(raw_body(signal).find("this is a WebSocket endpoint"), std::string::npos) << signal;
  EXPECT_EQ(raw_status(without_host(s["signal_url"].get<std::string>() + "x")), 401);
}

// An instance's own prefix without its trailing slash names nothing here
// (404); it was answered 421, as a path of another instance.
TEST(HttpTargets, AnInstancesOwnPrefixAloneIsNoOtherInstances) {
  ServerProcess server({"--set", "instance_index=2"});
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/i/2")), 404);
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/i/2/api/v1/health")), 200);
  for (const char* other : {"/i/3", "/i/20", "/i/2x", "/i/02/api/v1/health"})
    EXPECT_EQ(raw_status(raw_request(server.port(), "GET", other)), 421) << other;
}

namespace {

// A PATCH of a session's parameters written byte for byte.
std::string patch_params(const ServerProcess& server, const nlohmann::json& session, const std::string& content_type,
                         const std::string& body, const std::string& extra_headers = "") {
  return raw_request(server.port(), "PATCH", params_path(session),
                     authorization(session) + "Content-Type: " + content_type + "\r\n" + extra_headers, body);
}

}  // namespace

// A patch in a media type the resource does not take is told which it
// takes (RFC 5789 2.2).
TEST_F(Rest, APatchOfAnotherMediaTypeIsToldWhichAreTaken) {
  const nlohmann::json s = create();
  const std::string answer = patch_params(server_, s, "text/plain", R"({"post": {"exposure": 1}})");
  EXPECT_EQ(raw_status(answer), 415) << answer;
  EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json");
  EXPECT_EQ(raw_header(answer, "Accept-Patch"), "application/merge-patch+json, application/json") << answer;
}

// JSON is UTF-8 (RFC 8259 8.1): a body that says it is in another charset
// is refused, and changes nothing; UTF-8 said outright is taken.
TEST_F(Rest, AJsonBodyInAnotherCharsetIsRefused) {
  const nlohmann::json s = create();
  const int version = s["params"]["version"].get<int>();
  for (const char* type : {"application/merge-patch+json; charset=iso-8859-1", "application/json;charset=utf-16"}) {
    const std::string answer = patch_params(server_, s, type, R"({"post": {"exposure": 2}})");
    EXPECT_EQ(raw_status(answer), 415) << type << ": " << answer;
    EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json") << type;
  }
  const std::string posted = raw_request(server_.port(), "POST", "/api/v1/sessions",
                                         "Content-Type: application/json; charset=latin1\r\n", R"({"scene":"lens"})");
  EXPECT_EQ(raw_status(posted), 415) << posted;
  const std::string utf8 = patch_params(server_, s, "application/json; charset=UTF-8", R"({"post": {"exposure": 2}})");
  EXPECT_EQ(raw_status(utf8), 200) << utf8;
  EXPECT_EQ(nlohmann::json::parse(raw_body(utf8))["version"].get<int>(), version + 1);
}

// A field that holds one value, written twice: the library read the last
// Content-Type and the last Authorization, where a proxy in front may have
// judged the first; either twice is refused, and changes nothing.
TEST_F(Rest, AContentTypeOrAuthorizationWrittenTwiceIsRefused) {
  const nlohmann::json s = create();
  const int version = s["params"]["version"].get<int>();
  const std::string body = R"({"post": {"exposure": 2}})";
  for (const std::string& twice :
       {std::string("Content-Type: text/plain\r\n"), authorization(s), "Authorization: Bearer " + std::string(32, '0') + "\r\n"}) {
    const std::string answer = patch_params(server_, s, "application/merge-patch+json", body, twice);
    EXPECT_EQ(raw_status(answer), 400) << twice << answer;
    EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json") << twice;
  }
  const std::string posted =
      raw_request(server_.port(), "POST", "/api/v1/sessions",
                  "Content-Type: text/plain\r\nContent-Type: application/json\r\n", R"({"scene":"lens"})");
  EXPECT_EQ(raw_status(posted), 400) << posted;
  const std::string read = raw_request(server_.port(), "GET", params_path(s), authorization(s));
  EXPECT_EQ(nlohmann::json::parse(raw_body(read))["version"].get<int>(), version) << read;
  const std::string once = patch_params(server_, s, "application/merge-patch+json", body);
  EXPECT_EQ(raw_status(once), 200) << once;
}

// A parameter given twice in one Content-Type: the library took the first
// charset, where a proxy in front may take the last; the request is
// refused naming the header, and changes nothing. A ";" inside a quoted
// value separates nothing, and names differ by more than their case.
TEST_F(Rest, AContentTypeThatGivesAParameterTwiceIsRefused) {
  const nlohmann::json s = create();
  const int version = s["params"]["version"].get<int>();
  const std::string body = R"({"post": {"exposure": 2}})";
  for (const char* type : {"application/json; charset=utf-8; charset=latin1",
                           "application/merge-patch+json;charset=utf-8;CHARSET=utf-8", "application/json; a=1; A=2"}) {
    const std::string answer = patch_params(server_, s, type, body);
    EXPECT_EQ(raw_status(answer), 400) << type << ": " << answer;
    EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json") << type;
    EXPECT_NE(raw_body(answer).find("Content-Type"), std::string::npos) << type << ": " << answer;
  }
  const std::string posted =
      raw_request(server_.port(), "POST", "/api/v1/sessions",
                  "Content-Type: application/json; charset=utf-8; charset=utf-16\r\n", R"({"scene":"lens"})");
  EXPECT_EQ(raw_status(posted), 400) << posted;
  const std::string read = raw_request(server_.port(), "GET", params_path(s), authorization(s));
  EXPECT_EQ(nlohmann::json::parse(raw_body(read))["version"].get<int>(), version) << read;
  const std::string quoted = patch_params(server_, s, R"(application/json; a="x; charset=latin1"; charset=utf-8)", body);
  EXPECT_EQ(raw_status(quoted), 200) << quoted;
  // Thousands of names in one header, the last one a repeat: still found
  // (and looked up in a set, where a list searched once per name would
  // cost the main loop millions of comparisons).
  std::string many = "application/json";
  for (int i = 0; i < 1500; ++i) many += ";p" + std::to_string(i) + "=1";
  const std::string repeated = patch_params(server_, s, many + ";p0=2", body);
  EXPECT_EQ(raw_status(repeated), 400) << repeated.substr(0, 300);
  EXPECT_NE(raw_body(repeated).find("Content-Type"), std::string::npos) << repeated.substr(0, 300);
}

// Two holders of a session (its page and a script) that both read version
// N: the second patch sent with If-Match: "N" is refused 412 rather than
// overwrite the first unseen (RFC 9110 13.1.1), and changes nothing.
TEST_F(Rest, APatchSentWithAnOutdatedTagIsRefusedAndChangesNothing) {
  const nlohmann::json s = create();
  const std::string params = params_path(s);
  const std::string read = raw_request(server_.port(), "GET", params, authorization(s));
  ASSERT_EQ(raw_status(read), 200);
  const std::string tag = raw_header(read, "ETag");
  const int version = nlohmann::json::parse(raw_body(read))["version"].get<int>();
  EXPECT_EQ(tag, "\"" + std::to_string(version) + "\"");
  const std::string first = patch_params(server_, s, "application/merge-patch+json", R"({"post": {"exposure": 2}})",
                                         "If-Match: " + tag + "\r\n");
  ASSERT_EQ(raw_status(first), 200) << first;
  EXPECT_EQ(raw_header(first, "ETag"), "\"" + std::to_string(version + 1) + "\"");
  for (const std::string& stale : {tag, "W/\"" + std::to_string(version + 1) + "\"", std::string("\"x\", ") + tag}) {
    const std::string second = patch_params(server_, s, "application/merge-patch+json", R"({"post": {"exposure": 3}})",
                                            "If-Match: " + stale + "\r\n");
    EXPECT_EQ(raw_status(second), 412) << stale << ": " << second;
    EXPECT_EQ(raw_header(second, "Content-Type"), "application/problem+json");
    EXPECT_EQ(raw_header(second, "ETag"), "\"" + std::to_string(version + 1) + "\"");
  }
  const nlohmann::json now = caustic::testing::http("GET", session_url(s) + "/params", "", "", caustic::testing::bearer(s)).json();
  EXPECT_EQ(now["version"].get<int>(), version + 1);
  EXPECT_EQ(now["params"]["post"]["exposure"], 2);
  // "*" and a list that names the current tag go ahead.
  EXPECT_EQ(raw_status(patch_params(server_, s, "application/json", R"({"post": {"exposure": 2}})", "If-Match: *\r\n")),
            200);
  const std::string list = "\"x\", \"" + std::to_string(version + 2) + "\"";
  EXPECT_EQ(raw_status(patch_params(server_, s, "application/json", R"({"post": {"exposure": 2}})",
                                    "If-Match: " + list + "\r\n")),
            200)
      << list;
}

// An HTTP/1.0 client knows no 1xx answer, so its "Expect: 100-continue"
// is ignored (RFC 9110 10.1.1): the library answered "HTTP/1.0 100
// Continue" before the real answer, which such a client takes for the
// answer. An HTTP/1.1 client still gets its 100. Head and body go
// together: the 100, where one is sent, comes first all the same.
TEST(HttpExpect, AnHttp10ClientsExpectationIsIgnored) {
  ServerProcess server;
  const std::string body = R"({"x": 1})";  // 422: an unknown key, and no session made
  for (const std::string version : {"HTTP/1.0", "HTTP/1.1"}) {
    const std::string answer =
        raw_request(server.port(), "POST /api/v1/sessions " + version +
                                       "\r\nHost: 127.0.0.1\r\nExpect: 100-continue\r\nContent-Type: application/json"
                                       "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
    if (version == "HTTP/1.0") {
      EXPECT_EQ(answer.rfind("HTTP/1.0 422 ", 0), 0u) << answer.substr(0, 200);
    } else {
      EXPECT_EQ(answer.rfind("HTTP/1.1 100 Continue\r\n", 0), 0u) << answer.substr(0, 200);
      EXPECT_NE(answer.find("HTTP/1.1 422 "), std::string::npos) << answer.substr(0, 200);
    }
  }
}

// What api.md says of negotiation: Accept is not negotiated (a JSON path
// answers JSON to a browser's Accept), and OPTIONS, a cross-origin
// preflight included, is a method no path takes: 405 with Allow, and no
// CORS header that would let another origin's page in.
TEST(HttpNegotiation, AcceptIsNotNegotiatedAndOptionsIsNoPreflight) {
  ServerProcess server;
  const std::string html = raw_request(server.port(), "GET", "/api/v1/health", "Accept: text/html\r\n");
  EXPECT_EQ(raw_status(html), 200);
  EXPECT_EQ(raw_header(html, "Content-Type"), "application/json");
  EXPECT_EQ(raw_header(html, "Vary"), "");
  const std::string preflight = raw_request(server.port(), "OPTIONS", "/api/v1/sessions",
                                            "Origin: http://elsewhere.example\r\nAccess-Control-Request-Method: POST\r\n");
  EXPECT_EQ(raw_status(preflight), 405);
  EXPECT_EQ(raw_header(preflight, "Allow"), "POST");
  EXPECT_EQ(raw_header(preflight, "Access-Control-Allow-Origin"), "");
  EXPECT_EQ(raw_header(preflight, "Content-Type"), "application/problem+json");
}

// A client polling the parameters with the tag it holds hears only of a
// change: 304 without a body while the version stands (the 200's length,
// RFC 9110 8.6), 200 with the new tag once a patch came.
TEST_F(Rest, PollingTheParametersWithTheirTagAnswers304UntilAPatch) {
  const nlohmann::json s = create();
  const std::string params = params_path(s);
  const std::string first = raw_request(server_.port(), "GET", params, authorization(s));
  ASSERT_EQ(raw_status(first), 200);
  const std::string tag = raw_header(first, "ETag");
  for (const std::string method : {"GET", "HEAD"})
    for (const std::string& match : {tag, "W/" + tag, "\"x\", " + tag}) {
      const std::string again =
          raw_request(server_.port(), method, params, authorization(s) + "If-None-Match: " + match + "\r\n");
      EXPECT_EQ(raw_status(again), 304) << method << " " << match;
      EXPECT_EQ(raw_body(again), "") << method;
      EXPECT_EQ(raw_header(again, "ETag"), tag);
      EXPECT_EQ(raw_header(again, "Content-Length"), raw_header(first, "Content-Length"));
    }
  ASSERT_EQ(raw_status(patch_params(server_, s, "application/json", R"({"post": {"exposure": 2}})")), 200);
  const std::string changed =
      raw_request(server_.port(), "GET", params, authorization(s) + "If-None-Match: " + tag + "\r\n");
  EXPECT_EQ(raw_status(changed), 200);
  EXPECT_NE(raw_header(changed, "ETag"), tag);
  EXPECT_EQ(nlohmann::json::parse(raw_body(changed))["params"]["post"]["exposure"], 2);
}

// A problem's title is its status's phrase (RFC 9457 4.2.1), as RFC 9110
// names it: "Unprocessable Content" and "Content Too Large", not RFC 7231's.
TEST(HttpProblems, TitlesAreRfc9110sPhrases) {
  ServerProcess server;
  const std::string body = R"({"scene": "no such scene"})";
  const std::string unknown =
      raw_request(server.port(), "POST", "/api/v1/sessions", "Content-Type: application/json\r\n", body);
  EXPECT_EQ(raw_status(unknown), 422) << unknown;
  EXPECT_EQ(nlohmann::json::parse(raw_body(unknown))["title"], "Unprocessable Content");
  // The head alone, announcing a body over the limit.
  const std::string large = raw_request(server.port(), "POST", "/api/v1/sessions",
                                        "Content-Type: application/json\r\nContent-Length: 10000000\r\n");
  EXPECT_EQ(raw_status(large), 413) << large;
  EXPECT_EQ(nlohmann::json::parse(raw_body(large))["title"], "Content Too Large");
}

// A head over 16 KiB is refused before the library reads it: 414 when the
// request line alone is too long (the target, RFC 9112 3), 431 when the
// fields are (RFC 6585), each titled with its phrase.
TEST(HttpLimits, ALongTargetIs414AndLongFieldsAre431) {
  ServerProcess server;
  const std::string target = raw_request(server.port(), "GET", "/api/v1/scenes/" + std::string(20000, 'a'));
  EXPECT_EQ(raw_status(target), 414) << target.substr(0, 400);
  EXPECT_EQ(nlohmann::json::parse(raw_body(target))["title"], "URI Too Long");
  const std::string fields =
      raw_request(server.port(), "GET", "/api/v1/health", "X-Pad: " + std::string(20000, 'a') + "\r\n");
  EXPECT_EQ(raw_status(fields), 431) << fields.substr(0, 400);
  EXPECT_EQ(nlohmann::json::parse(raw_body(fields))["title"], "Request Header Fields Too Large");
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/api/v1/health")), 200);
}
