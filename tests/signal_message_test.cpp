// SPDX-License-Identifier: LGPL-2.1-or-later
// The signalling parser on its own: each message kind, and the inputs that
// once reached a library precondition instead of an error.
#include "signal_message.hpp"

#include <glib.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <vector>

namespace caustic::server {
namespace {

// A GLib critical is a precondition the caller broke: here it fails the test
// (the process aborts) instead of scrolling past in the log.
class FatalCriticals : public ::testing::Environment {
 public:
  void SetUp() override {
    g_log_set_always_fatal(static_cast<GLogLevelFlags>(G_LOG_LEVEL_CRITICAL | G_LOG_LEVEL_ERROR));
  }
};
[[maybe_unused]] const auto* const kFatal = ::testing::AddGlobalTestEnvironment(new FatalCriticals);

const std::string kSdp =
    "v=0\r\no=- 0 0 IN IP4 127.0.0.1\r\ns=-\r\nt=0 0\r\n"
    "m=video 9 UDP/TLS/RTP/SAVPF 96\r\nc=IN IP4 0.0.0.0\r\na=rtpmap:96 VP8/90000\r\n";

std::string error_of(const std::string& text) {
  const SignalMessage m = parse_signal_message(text);
  const auto* e = std::get_if<SignalError>(&m);
  return e ? e->message : std::string();
}

TEST(SignalMessage, AnswerWithMediaIsTaken) {
  const std::string text = nlohmann::json{{"type", "answer"}, {"sdp", kSdp}}.dump();
  const SignalMessage m = parse_signal_message(text);
  ASSERT_TRUE(std::holds_alternative<SignalAnswer>(m)) << error_of(text);
  EXPECT_EQ(std::get<SignalAnswer>(m).sdp, kSdp);
}

TEST(SignalMessage, AnswerThatIsNotSdpIsAnError) {
  // The empty one once reached gst_sdp_message_parse_buffer's size != 0 assertion.
  for (const std::string& sdp : std::vector<std::string>{"", "hello", "v=0\r\n", std::string("v=0\0m=video", 11)}) {
    const std::string text = nlohmann::json{{"type", "answer"}, {"sdp", sdp}}.dump();
    EXPECT_EQ(error_of(text), "answer: \"sdp\" is not valid SDP") << text;
  }
  EXPECT_EQ(error_of(R"({"type":"answer","sdp":7})"), "answer: \"sdp\" must be a string");
  EXPECT_EQ(error_of(R"({"type":"answer"})"), "answer: \"sdp\" must be a string");
}

TEST(SignalMessage, IceCandidateAndItsLimits) {
  const SignalMessage m = parse_signal_message(
      R"({"type":"ice","candidate":"candidate:1 1 UDP 2122252543 127.0.0.1 40000 typ host","sdpMLineIndex":0})");
  ASSERT_TRUE(std::holds_alternative<SignalIce>(m));
  EXPECT_EQ(std::get<SignalIce>(m).mline, 0u);
  // The end of candidates is an empty one.
  EXPECT_TRUE(std::holds_alternative<SignalIce>(parse_signal_message(R"({"type":"ice","candidate":"","sdpMLineIndex":0})")));
  for (const char* bad : {R"({"type":"ice","candidate":"x","sdpMLineIndex":64})",
                          R"({"type":"ice","candidate":"x","sdpMLineIndex":-1})",
                          R"({"type":"ice","candidate":"x","sdpMLineIndex":1.5})",
                          R"({"type":"ice","candidate":"x"})", R"({"type":"ice","sdpMLineIndex":0})"})
    EXPECT_NE(error_of(bad), "") << bad;
  EXPECT_EQ(error_of(R"({"type":"ice","candidate":"a\u0001b","sdpMLineIndex":0})"),
            "ice: the candidate must be printable ASCII");
  // Printable but not a candidate: said, not handed to the ICE agent to drop.
  for (const char* bad : {R"({"type":"ice","candidate":"garbage","sdpMLineIndex":0})",
                          R"({"type":"ice","candidate":"candidate:1 1 UDP 2122252543 127.0.0.1 40000","sdpMLineIndex":0})",
                          R"({"type":"ice","candidate":"1 1 UDP 2122252543 127.0.0.1 40000 typ host","sdpMLineIndex":0})"})
    EXPECT_NE(error_of(bad).find("is not an ICE candidate"), std::string::npos) << bad;
  // A browser's mDNS candidate, with the extensions after the type.
  EXPECT_EQ(error_of(R"({"type":"ice","candidate":"candidate:842163049 1 udp 1677729535 )"
                     R"(4b0c0a4e-9d1c.local 56143 typ srflx raddr 0.0.0.0 rport 0 generation 0 ufrag sNQr",)"
                     R"("sdpMLineIndex":0})"),
            "");
}

TEST(SignalMessage, PingAndMalformedMessages) {
  EXPECT_TRUE(std::holds_alternative<SignalPing>(parse_signal_message(R"({"type":"ping"})")));
  for (const char* bad : {"", "null", "[]", "{", R"({"type":1})", R"({"kind":"ping"})"})
    EXPECT_EQ(error_of(bad), "a signalling message is a JSON object with a string \"type\"") << bad;
  EXPECT_EQ(error_of(R"({"type":"offer"})"), "unknown message type");
  // Errors never echo what came in.
  EXPECT_EQ(error_of(R"({"type":"<script>"})"), "unknown message type");
  EXPECT_NE(error_of(std::string(kMaxSignalMessageBytes + 1, ' ')), "");
}

}  // namespace
}  // namespace caustic::server
