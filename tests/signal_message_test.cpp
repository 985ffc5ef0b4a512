// SPDX-License-Identifier: LGPL-2.1-or-later
// The signalling parser on its own: each message kind, the inputs that
// once reached a library precondition instead of an error, and the answers
// that do not fit their offer.
#include "signal_message.hpp"
#include "sdp_edit.hpp"

#include <glib.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <vector>

namespace caustic::server {
namespace {

using caustic::testing::replaced;

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

// An offer in webrtcbin's shape (video it sends, then the data channel) and
// the answer a browser gives it; the cases below change one thing each.
const std::string kOffer =
    "v=0\r\no=- 1 0 IN IP4 0.0.0.0\r\ns=-\r\nt=0 0\r\na=group:BUNDLE video0 application1\r\n"
    "m=video 9 UDP/TLS/RTP/SAVPF 96 97\r\nc=IN IP4 0.0.0.0\r\na=setup:actpass\r\na=sendonly\r\n"
    "a=rtpmap:96 VP8/90000\r\na=mid:video0\r\n"
    "m=application 0 UDP/DTLS/SCTP webrtc-datachannel\r\nc=IN IP4 0.0.0.0\r\na=setup:actpass\r\n"
    "a=mid:application1\r\na=sctp-port:5000\r\n";
// A self-signed certificate (made with openssl for these tests) and its
// digests as `openssl x509 -noout -fingerprint -sha256` (and -sha1) print them.
const std::string kCertificate =
    "-----BEGIN CERTIFICATE-----\n"
    "MIIBhzCCAS2gAwIBAgIUQJ8QhVfR6wXE9eGpf0SX5lH4kkAwCgYIKoZIzj0EAwIw\n"
    "GDEWMBQGA1UEAwwNY2F1c3RpY2QtdGVzdDAgFw0yNjEyMDYxMDE3MTNaGA8yMTI2\n"
    "MTExMjEwMTcxM1owGDEWMBQGA1UEAwwNY2F1c3RpY2QtdGVzdDBZMBMGByqGSM49\n"
    "AgEGCCqGSM49AwEHA0IABLsoGZ8xwS2jZ/hI6s16Ipake5VQfB015EwrXfr6mxU3\n"
    "31Ybo0yPsqairaqq7VZLWWbffLaq5TibmF29RD2nTs+jUzBRMB0GA1UdDgQWBBRo\n"
    "sT2TpAbI4ify9lIufaadvmMyPzAfBgNVHSMEGDAWgBRosT2TpAbI4ify9lIufaad\n"
    "vmMyPzAPBgNVHRMBAf8EBTADAQH/MAoGCCqGSM49BAMCA0gAMEUCIGDMjSriRi2A\n"
    "ok7FesbF2gx7MFeC6nbf0Zs563HnGwLYAiEA4hTw+Sn/JLrh+Qs/5LTHvgGpa9FS\n"
    "eTstietWrnZEwbY=\n"
    "-----END CERTIFICATE-----\n";
const std::string kSha256 =
    "B2:4E:A1:0C:C4:AE:C6:98:4A:90:09:94:AE:65:5C:03:C4:85:B3:C5:6B:5E:5D:2C:84:7F:35:31:11:0D:C1:8E";
const std::string kSha1 = "42:29:45:2D:2F:12:0C:A0:4B:5B:DE:36:D9:63:76:00:78:44:03:0B";
// What every answered m-line carries for its transport.
const std::string kTransport = "a=ice-ufrag:uf\r\na=ice-pwd:0123456789abcdefghijkl\r\na=fingerprint:sha-256 " + kSha256 + "\r\n";
const std::string kVideo =
    "m=video 9 UDP/TLS/RTP/SAVPF 96\r\nc=IN IP4 0.0.0.0\r\n" + kTransport + "a=setup:active\r\na=recvonly\r\n"
    "a=rtpmap:96 VP8/90000\r\na=mid:video0\r\n";
const std::string kChannel =
    "m=application 9 UDP/DTLS/SCTP webrtc-datachannel\r\nc=IN IP4 0.0.0.0\r\n" + kTransport + "a=setup:active\r\n"
    "a=mid:application1\r\na=sctp-port:5000\r\n";
const std::string kHead = "v=0\r\no=- 2 0 IN IP4 0.0.0.0\r\ns=-\r\nt=0 0\r\n";

std::string lower_hex(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string with_direction(std::string media, const std::string& direction) {
  const std::size_t at = media.find("a=recvonly\r\n");
  return media.replace(at, 12, direction.empty() ? "" : "a=" + direction + "\r\n");
}

TEST(SignalMessage, AnAnswerThatFitsTheOfferIsTaken) {
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + kChannel), "");
  // A rejected m-line (port 0) needs no direction, nor a transport.
  std::string rejected = replaced(with_direction(kVideo, "sendrecv"), kTransport, "");
  rejected.replace(rejected.find("m=video 9"), 9, "m=video 0");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + rejected + kChannel), "");
}

TEST(SignalMessage, AnAnswerWhoseMLinesDoNotFitTheOfferIsNamed) {
  // Swapped m-lines once aborted the server inside webrtcbin.
  const std::string swapped = answer_mismatch(kOffer, kHead + kChannel + kVideo);
  EXPECT_EQ(swapped,
            "answer: m-line 0 must answer the offer's video m-line (UDP/TLS/RTP/SAVPF), the m-lines in the offer's order");
  // An RTP m-line of the application kind where the data channel was.
  std::string rtp_application = kVideo;
  rtp_application.replace(0, 7, "m=application");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + rtp_application),
            "answer: m-line 1 must answer the offer's application m-line (UDP/DTLS/SCTP webrtc-datachannel), the "
            "m-lines in the offer's order");
  std::string audio = kVideo;
  audio.replace(0, 7, "m=audio");
  EXPECT_NE(answer_mismatch(kOffer, kHead + audio + kChannel), "");
  std::string other_proto = kVideo;
  other_proto.replace(other_proto.find("UDP/TLS/RTP/SAVPF"), 17, "RTP/AVP");
  EXPECT_NE(answer_mismatch(kOffer, kHead + other_proto + kChannel), "");
  for (const std::string& count : {kHead + kVideo, kHead + kVideo + kChannel + kChannel})
    EXPECT_EQ(answer_mismatch(kOffer, count), "answer: needs one m-line for each of the offer's 2, in the offer's order");
}

TEST(SignalMessage, AnAnswerKeepsTheOffersMidsAndItsBundleTag) {
  const std::string bundle = "a=group:BUNDLE video0 application1\r\n";
  EXPECT_EQ(answer_mismatch(kOffer, kHead + bundle + kVideo + kChannel), "");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + "a=group:BUNDLE video0\r\n" + kVideo + kChannel), "") << "fewer bundled";
  // Mids that trade places, or a group tagged by the data channel, once
  // aborted the server inside webrtcbin.
  const std::string traded =
      replaced(replaced(replaced(kHead + bundle + kVideo + kChannel, "a=mid:video0", "a=mid:x"), "a=mid:application1",
                        "a=mid:video0"),
               "a=mid:x", "a=mid:application1");
  EXPECT_EQ(answer_mismatch(kOffer, traded), "answer: m-line 0 must keep the offer's mid (video0)");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, "a=mid:video0\r\n", "") + kChannel),
            "answer: m-line 0 must keep the offer's mid (video0)");
  const std::string expected =
      "answer: a BUNDLE group must start with the offer's first bundled mid (video0) and name only the offer's "
      "bundled mids, each once";
  for (const char* group : {"application1 video0", "application1", "video0 video0", "video0 unknown", "",
                                   "video0\r\na=group:BUNDLE application1"})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + "a=group:BUNDLE " + group + "\r\n" + kVideo + kChannel), expected)
        << group;
}

TEST(SignalMessage, WhatTheLibrariesTakeOnlyAsAProgrammingErrorIsRefused) {
  // A second session-level credential where an m-line has none of its own
  // aborted the server inside webrtcbin; duplicates are refused anywhere.
  EXPECT_EQ(answer_mismatch(kOffer, kHead + "a=ice-ufrag:aaaaaaaa\r\na=ice-ufrag:bbbbbbbb\r\n" + kVideo + kChannel),
            "answer: at most one session-level a=ice-ufrag");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + "a=ice-pwd:p\r\na=ice-pwd:q\r\n" + kVideo + kChannel),
            "answer: at most one session-level a=ice-pwd");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=ice-pwd:p\r\na=ice-pwd:q\r\n" + kChannel),
            "answer: m-line 0 has more than one a=ice-pwd");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + "a=ice-ufrag:aaaaaaaa\r\n" + kVideo + kChannel), "") << "one is fine";
  // GLib criticals, not aborts, but calls the libraries rule out.
  for (const char* ssrc : {"a=ssrc:0 cname:x", "a=ssrc:4294967296 cname:x", "a=ssrc:-1 cname:x", "a=ssrc:"})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + ssrc + "\r\n" + kChannel),
              "answer: m-line 0: an SSRC must be in [1, 2^32 - 1]")
        << ssrc;
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=ssrc:4294967295 cname:x\r\n" + kChannel), "");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=candidate:1 1 udp 1 127.0.0.1 9 typ host\r\n" + kChannel), "");
  // Component 0 was a critical; 2 to 256 a warning a line (RTCP shares
  // RTP's component); a TCP candidate without its tcptype a critical.
  for (const std::string candidate : {"1 0 udp 1 127.0.0.1 9 typ host", "1 2 udp 1 127.0.0.1 9 typ host"})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=candidate:" + candidate + "\r\n" + kChannel),
              "answer: m-line 0: a candidate's component must be 1 (RTCP is multiplexed with RTP)");
  for (const std::string candidate : {"1 1 TCP 1 127.0.0.1 9 typ host", "1 1 tcp 1 127.0.0.1 9 typ srflx raddr 0.0.0.0",
                                      "1 1 tcp 1 127.0.0.1 9 typ host tcptype", "1 1 tcp 1 127.0.0.1 9 typ host tcptype x"})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=candidate:" + candidate + "\r\n" + kChannel),
              "answer: m-line 0: a TCP candidate needs a tcptype of active, passive or so")
        << candidate;
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=candidate:1 1 TCP 1 127.0.0.1 9 typ host tcptype passive\r\n" +
                                        kChannel),
            "");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=candidate:1 1 sctp 1 127.0.0.1 9 typ host\r\n" + kChannel),
            "answer: m-line 0: a candidate's transport must be UDP or TCP");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=candidate:1 1 udp 1 127.0.0.1 9\r\n" + kChannel),
            "answer: m-line 0: an a=candidate line is not an ICE candidate (... typ ...)");
  for (const char* fmtp : {"a=fmtp:96 a-mid=foo", "a=fmtp:96 max-fr=30;EXTMAP-1=x", "a=x-foo:1\r\na=fmtp:96 x-foo=2"})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + fmtp + "\r\n" + kChannel),
              "answer: m-line 0: an fmtp parameter must not be named like an attribute (a-..., extmap-..., or the "
              "m-line's own)")
        << fmtp;
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + "a=fmtp:96 max-fr=30;max-fs=3600\r\n" + kChannel), "");
  EXPECT_EQ(error_of(R"({"type":"ice","candidate":"candidate:1 0 UDP 2122252543 127.0.0.1 40000 typ host",)"
                     R"("sdpMLineIndex":0})"),
            "ice: a candidate's component must be 1 (RTCP is multiplexed with RTP)");
  EXPECT_EQ(error_of(R"({"type":"ice","candidate":"candidate:1 1 TCP 2122252543 127.0.0.1 9999 typ host",)"
                     R"("sdpMLineIndex":0})"),
            "ice: a TCP candidate needs a tcptype of active, passive or so");
  EXPECT_EQ(error_of(R"({"type":"ice","candidate":"candidate:1 1 TCP 2122252543 127.0.0.1 9 typ host tcptype active",)"
                     R"("sdpMLineIndex":0})"),
            "");
}

TEST(SignalMessage, ASendonlyMLineIsAnsweredRecvonly) {
  const std::string expected = "answer: m-line 0 answers a sendonly video m-line: it must be recvonly (or rejected, port 0)";
  // inactive: webrtcbin sent the video all the same.
  EXPECT_EQ(answer_mismatch(kOffer, kHead + with_direction(kVideo, "inactive") + kChannel), expected);
  EXPECT_EQ(answer_mismatch(kOffer, kHead + with_direction(kVideo, "sendonly") + kChannel), expected);
  EXPECT_EQ(answer_mismatch(kOffer, kHead + with_direction(kVideo, "sendrecv") + kChannel), expected);
  EXPECT_EQ(answer_mismatch(kOffer, kHead + with_direction(kVideo, "") + kChannel), expected) << "none is sendrecv";
  // A session-level direction counts where the m-line has none.
  EXPECT_EQ(answer_mismatch(kOffer, kHead + "a=recvonly\r\n" + with_direction(kVideo, "") + kChannel), "");
}

TEST(SignalMessage, EachAnsweredTransportHasCredentialsARoleAndAFingerprint) {
  // Each of these webrtcbin refused only in its debug log, the viewer left waiting.
  EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, "a=ice-ufrag:uf\r\n", "") + kChannel),
            "answer: m-line 0 needs an a=ice-ufrag");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kVideo + replaced(kChannel, "a=ice-pwd:0123456789abcdefghijkl\r\n", "")),
            "answer: m-line 1 needs an a=ice-pwd");
  const std::string role = "answer: m-line 0 needs one a=setup of its own, active or passive (the answer's DTLS role)";
  for (const std::string setup : {"", "a=setup:actpass\r\n", "a=setup:holdconn\r\n", "a=setup:garbage\r\n",
                                  "a=setup:active\r\na=setup:passive\r\n"})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, "a=setup:active\r\n", setup) + kChannel), role) << setup;
  EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, "a=setup:active", "a=setup:passive") + kChannel), "");
  const std::string digest =
      "answer: m-line 0 needs an a=fingerprint of its DTLS certificate: sha-1, sha-256, sha-384 or sha-512, its "
      "digest in hex pairs";
  EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, "a=fingerprint:sha-256 " + kSha256 + "\r\n", "") + kChannel),
            digest);
  for (const std::string& bad : {"sha-256 " + kSha256.substr(3), "sha-256 " + kSha256 + ":00", "sha-1 " + kSha256,
                                "md5 " + kSha1.substr(0, 47), "sha-224 " + kSha256.substr(0, 83), "foo-256 " + kSha256,
                                "sha-256 " + replaced(kSha256, "B2", "ZZ"), "sha-256 " + replaced(kSha256, ":", "-"),
                                std::string("sha-256")})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, "sha-256 " + kSha256, bad) + kChannel), digest) << bad;
  // A fingerprint of a hash the server does not know, beside one it does,
  // is ignored (RFC 8122 5), as is a second of a known hash that is malformed.
  for (const std::string& beside : {"sha-224 " + kSha256.substr(0, 83), "sha-256 " + kSha256.substr(3)})
    EXPECT_EQ(answer_mismatch(kOffer, kHead + replaced(kVideo, kTransport, kTransport + "a=fingerprint:" + beside + "\r\n") +
                                          kChannel),
              "")
        << beside;
  // Credentials and fingerprints at the session level serve every m-line
  // without its own; the DTLS role does not (webrtcbin reads it per m-line,
  // and made both ends DTLS clients).
  const std::string bare_video = replaced(kVideo, kTransport, ""), bare_channel = replaced(kChannel, kTransport, "");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kTransport + bare_video + bare_channel), "");
  EXPECT_EQ(answer_mismatch(kOffer, kHead + kTransport + "a=setup:active\r\n" +
                                        replaced(bare_video, "a=setup:active\r\n", "") + bare_channel),
            role);
}

TEST(SignalMessage, TheViewersCertificateIsHeldAgainstItsFingerprint) {
  const auto sha256 = parse_fingerprint("sha-256 " + kSha256), sha1 = parse_fingerprint("SHA-1 " + kSha1);
  ASSERT_TRUE(sha256 && sha1);
  EXPECT_EQ(sha256->hash, "sha-256");
  EXPECT_EQ(sha1->hash, "sha-1");
  EXPECT_EQ(sha256->digest.size(), 32u);
  EXPECT_EQ(sha256->digest.front(), 0xB2);
  EXPECT_TRUE(certificate_matches(kCertificate, {*sha256}));
  EXPECT_TRUE(certificate_matches(kCertificate, {*sha1}));
  // Lowercase hex is the same digest.
  EXPECT_TRUE(certificate_matches(kCertificate, {*parse_fingerprint("sha-256 " + lower_hex(kSha256))}));
  // One byte off, another hash's label, no fingerprint, no certificate: refused.
  auto off = *sha256;
  off.digest.back() ^= 1;
  EXPECT_FALSE(certificate_matches(kCertificate, {off}));
  auto relabelled = *sha256;
  relabelled.hash = "sha-512";
  EXPECT_FALSE(certificate_matches(kCertificate, {relabelled}));
  EXPECT_FALSE(certificate_matches(kCertificate, {}));
  EXPECT_FALSE(certificate_matches("", {*sha256}));
  EXPECT_FALSE(certificate_matches(replaced(kCertificate, "MIIB", "MIIC"), {*sha256}));
  // Any of several will do (RFC 8122 allows more than one).
  EXPECT_TRUE(certificate_matches(kCertificate, {off, *sha1}));
  // The answer's first transport gives them.
  const auto from_answer = answer_fingerprints(kHead + kVideo + kChannel);
  ASSERT_EQ(from_answer.size(), 1u);
  EXPECT_EQ(from_answer[0].digest, sha256->digest);
}

TEST(SignalMessage, AnAnswerWithoutAnOfferOrSdpIsRefusedWithoutQuotingIt) {
  EXPECT_EQ(answer_mismatch("", kHead + kVideo + kChannel), "answer: there is no offer to answer");
  EXPECT_EQ(answer_mismatch(kOffer, ""), "answer: \"sdp\" is not valid SDP");
  std::string odd = kChannel;
  odd.replace(0, 13, "m=<script>");
  const std::string why = answer_mismatch(kOffer, kHead + kVideo + odd);
  EXPECT_NE(why, "");
  EXPECT_EQ(why.find("script"), std::string::npos) << why;
}

}  // namespace
}  // namespace caustic::server
