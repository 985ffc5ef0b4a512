// SPDX-License-Identifier: LGPL-2.1-or-later
// What causticd reads from and makes for Janus, without a Janus: the
// viewer token's format, and answers of every shape read as errors, never
// as an exception out of the library's callback.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../src/server/janus_requests.hpp"
#include "../src/server/janus_admin.hpp"

#include <string>

using nlohmann::json;

TEST(JanusToken, IsTheFormatJanusChecks) {
  // The expected value is openssl's, not this code's:
  //   printf %s '1700000000,janus,janus.plugin.streaming' | openssl dgst -sha1 -hmac secret -binary | base64
  EXPECT_EQ(caustic::server::janus_token("secret", 1700000000),
            "1700000000,janus,janus.plugin.streaming:dwvIvxr0mdOVyZJ3U4ZTq/+8q5s=");
}

// Whatever answers on Janus's admin port, its body is read without an
// exception (it is read inside a libsoup callback) and said as an error.
TEST(JanusAnswer, OddBodiesAreErrorsNotCrashes) {
  using caustic::server::JanusAdmin;
  static constexpr char kNulInside[] = "{\"janus\":\"success\"}\0{\"janus\":\"error\"}";
  const auto ok = JanusAdmin::parse_answer(R"({"janus":"success","response":{"streaming":"created","id":7}})");
  EXPECT_EQ(ok.error, "");
  EXPECT_EQ(ok.response.value("id", 0), 7);
  const auto gone = JanusAdmin::parse_answer(
      R"({"janus":"success","response":{"error_code":455,"error":"No such mountpoint/stream 7"}})");
  EXPECT_EQ(gone.error_code, 455);
  EXPECT_EQ(gone.error, "No such mountpoint/stream 7");
  EXPECT_EQ(JanusAdmin::parse_answer(R"({"janus":"error","error":{"code":403,"reason":"Unauthorized request"}})").error,
            "Janus refused: Unauthorized request");
  for (const std::string& body :
       {std::string("<html>bad gateway</html>"), std::string(""), std::string("[1,2]"), std::string("\"success\""),
        std::string("{\"janus\":5}"), std::string("{\"janus\":\"error\",\"error\":\"text\"}"),
        std::string("{\"janus\":\"error\",\"error\":{\"reason\":7}}"),
        std::string(kNulInside, sizeof kNulInside - 1),
        std::string("{\"janus\":\"error\",\"error\":{\"reason\":\"\xff\xfe\"}}")}) {
    JanusAdmin::Answer a;
    EXPECT_NO_THROW(a = JanusAdmin::parse_answer(body)) << body;
    EXPECT_NE(a.error, "") << body;
  }
  // Fields of other types inside a success: the plugin refused, no throw.
  JanusAdmin::Answer odd;
  EXPECT_NO_THROW(odd = JanusAdmin::parse_answer(R"({"janus":"success","response":{"error_code":"455","error":[1]}})"));
  EXPECT_EQ(odd.error, "the streaming plugin refused");
  EXPECT_EQ(odd.error_code, -1);
  EXPECT_NO_THROW(odd = JanusAdmin::parse_answer(R"({"janus":"success","response":"text"})"));
  EXPECT_EQ(odd.error, "");
  EXPECT_TRUE(odd.response.is_object());
}

TEST(JanusAnswer, PortsOfOtherTypesAreUnusableNotCrashes) {
  // A field of another type threw out of the library's callback (an abort).
  using caustic::server::Mountpoint;
  using caustic::server::read_ports;
  const json good = json::parse(R"({"stream":{"ports":[{"type":"video","port":5004,"rtcp_port":5005},
                                                        {"type":"data","port":5006}]}})");
  Mountpoint m;
  ASSERT_TRUE(read_ports(good, m));
  EXPECT_EQ(m.video_port, 5004);
  EXPECT_EQ(m.data_port, 5006);
  for (const char* odd :
       {R"({"stream":"x"})", R"({"stream":{"ports":{}}})", R"({"stream":{"ports":[1,"a",null]}})",
        R"({"stream":{"ports":[{"type":"video","port":"5004","rtcp_port":5005},{"type":"data","port":5006}]}})",
        R"({"stream":{"ports":[{"type":7,"port":5004},{"type":"data","port":5006}]}})",
        R"({"stream":{"ports":[{"type":"video","port":70000,"rtcp_port":70001},{"type":"data","port":5006}]}})",
        R"({"stream":{"ports":[{"type":"video","port":-2,"rtcp_port":-1},{"type":"data","port":5006}]}})", "[]", "7"}) {
    Mountpoint odd_m;
    bool usable = true;
    EXPECT_NO_THROW(usable = read_ports(json::parse(odd), odd_m)) << odd;
    EXPECT_FALSE(usable) << odd;
  }
}
