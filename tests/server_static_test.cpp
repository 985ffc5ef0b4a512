// SPDX-License-Identifier: LGPL-2.1-or-later
// The web client's files as causticd serves them: from web/ and nothing
// else, and cached by validation (an ETag, 304 when unchanged) while the
// API's answers are never stored.
#include "raw_http.hpp"
#include "server_process.hpp"
#include "web_folder.hpp"

#include <filesystem>

using caustic::testing::http;
using caustic::testing::raw_body;
using caustic::testing::raw_header;
using caustic::testing::raw_request;
using caustic::testing::raw_status;
using caustic::testing::Response;
using caustic::testing::ServerProcess;
using caustic::testing::WebFolder;

namespace {

constexpr const char* kPage = "<!doctype html><title>ok</title>";

}  // namespace

TEST(StaticFiles, ServeWebAndNothingElse) {
  const WebFolder web({{"index.html", kPage}, {"sub/app.js", "console.log(1);"}, {".secret.txt", "hidden"}});
  std::filesystem::create_symlink("/etc/passwd", web.path() / "passwd.txt");
  std::filesystem::create_directory_symlink("/etc", web.path() / "etc");
  ServerProcess server({"--web-dir", web.dir()});
  const Response index = http("GET", server.url() + "/");
  EXPECT_EQ(index.status, 200u);
  EXPECT_EQ(index.content_type, "text/html");
  EXPECT_EQ(http("GET", server.url() + "/sub/app.js").content_type, "text/javascript");
  for (const char* path : {"/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/%2E%2E%2F%2E%2E%2Fetc%2Fpasswd",
                           "/sub/..%2f..%2f..%2fetc/passwd", "/passwd.txt", "/etc/passwd", "/.secret.txt",
                           "/sub%00.html", "/%5c..%5cetc", "/missing.html", "/index.exe", "/index.html/",
                           "/index.html//", "/sub//app.js"})
  {
    // libsoup itself answers 400 to some malformed paths; either way, no file.
    const int status = raw_status(raw_request(server.port(), "GET", path));
    EXPECT_TRUE(status == 404 || status == 400) << path << ": " << status;
  }
}

TEST(StaticFiles, AreRevalidatedByTheirETagWhileTheApiIsNeverStored) {
  const WebFolder web({{"index.html", kPage}, {"app.js", "console.log(1);"}});
  ServerProcess server({"--web-dir", web.dir()});
  const std::string first = raw_request(server.port(), "GET", "/app.js");
  ASSERT_EQ(raw_status(first), 200);
  EXPECT_EQ(raw_body(first), "console.log(1);");
  EXPECT_EQ(raw_header(first, "Cache-Control"), "no-cache");
  const std::string etag = raw_header(first, "ETag");
  ASSERT_GE(etag.size(), 3u);
  EXPECT_EQ(etag.front(), '"');
  EXPECT_EQ(etag.back(), '"');
  // Asked again with its tag (as a browser revalidates, or weakly, or in a
  // list): 304, no bytes.
  for (const std::string& match : {etag, "W/" + etag, "\"other\", " + etag}) {
    const std::string again = raw_request(server.port(), "GET", "/app.js", "If-None-Match: " + match + "\r\n");
    EXPECT_EQ(raw_status(again), 304) << match;
    EXPECT_EQ(raw_body(again), "") << match;
    EXPECT_EQ(raw_header(again, "ETag"), etag) << match;
  }
  EXPECT_EQ(raw_status(raw_request(server.port(), "GET", "/app.js", "If-None-Match: \"other\"\r\n")), 200);
  // A page's tag is its own, and it keeps its policy.
  const std::string page = raw_request(server.port(), "GET", "/");
  EXPECT_EQ(raw_status(page), 200);
  EXPECT_NE(raw_header(page, "ETag"), etag);
  EXPECT_NE(raw_header(page, "Content-Security-Policy"), "");
  // Changed (an upgrade's copy): a new tag, and the old one gets the bytes.
  web.write("app.js", "console.log(22);");
  const std::string changed = raw_request(server.port(), "GET", "/app.js", "If-None-Match: " + etag + "\r\n");
  EXPECT_EQ(raw_status(changed), 200);
  EXPECT_EQ(raw_body(changed), "console.log(22);");
  EXPECT_NE(raw_header(changed, "ETag"), etag);
  // A server whose pages may reach a broadcast server: the same page file
  // with another policy, so another tag (a 304 would keep the old policy).
  {
    ServerProcess broadcasting({"--web-dir", web.dir(), "--set", "janus_ws_url=ws://127.0.0.1:8188/"});
    const std::string other =
        raw_request(broadcasting.port(), "GET", "/", "If-None-Match: " + raw_header(page, "ETag") + "\r\n");
    EXPECT_EQ(raw_status(other), 200);
    EXPECT_NE(raw_header(other, "ETag"), raw_header(page, "ETag"));
    EXPECT_NE(raw_header(other, "Content-Security-Policy").find("ws://127.0.0.1:8188"), std::string::npos)
        << raw_header(other, "Content-Security-Policy");
  }
  // The API's answers are never stored, and carry no tag.
  const std::string health = raw_request(server.port(), "GET", "/api/v1/health");
  EXPECT_EQ(raw_header(health, "Cache-Control"), "no-store");
  EXPECT_EQ(raw_header(health, "ETag"), "");
}

// A browser copies the headers of a 304 onto the response it kept (RFC 9111
// 4.3.4): a page's must carry the page's own policy, whose hash admits its
// import map, not the API's, which would block it after a reload.
TEST(StaticFiles, ANotModifiedPageKeepsItsPolicy) {
  const WebFolder web({{"index.html", "<!doctype html><script type=\"importmap\">{\"imports\": {}}</script>"}});
  ServerProcess server({"--web-dir", web.dir()});
  const std::string first = raw_request(server.port(), "GET", "/");
  ASSERT_EQ(raw_status(first), 200);
  const std::string policy = raw_header(first, "Content-Security-Policy");
  ASSERT_NE(policy.find("'sha256-"), std::string::npos) << policy;
  const std::string again =
      raw_request(server.port(), "GET", "/", "If-None-Match: " + raw_header(first, "ETag") + "\r\n");
  ASSERT_EQ(raw_status(again), 304);
  EXPECT_EQ(raw_header(again, "Content-Security-Policy"), policy);
}

// A 304's Content-Length, if any, is the 200's (RFC 9110 8.6): a cache may
// copy it onto the file it kept, and 0 there would empty the file.
TEST(StaticFiles, ANotModifiedFileTellsItsOwnLength) {
  const WebFolder web({{"app.js", "console.log(1);"}});
  ServerProcess server({"--web-dir", web.dir()});
  const std::string first = raw_request(server.port(), "GET", "/app.js");
  ASSERT_EQ(raw_status(first), 200);
  EXPECT_EQ(raw_header(first, "Content-Length"), "15");
  for (const std::string method : {"GET", "HEAD"}) {
    const std::string again =
        raw_request(server.port(), method, "/app.js", "If-None-Match: " + raw_header(first, "ETag") + "\r\n");
    EXPECT_EQ(raw_status(again), 304) << method;
    const std::string length = raw_header(again, "Content-Length");
    EXPECT_TRUE(length.empty() || length == "15") << method << ": " << length;
    EXPECT_EQ(raw_body(again), "") << method;
  }
}
