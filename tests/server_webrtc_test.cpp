// SPDX-License-Identifier: LGPL-2.1-or-later
// End to end without a browser: a second webrtcbin, as the viewer, connects
// over loopback through the real signalling WebSocket and decodes frames.
#include "server_process.hpp"
#include "webrtc_peer.hpp"

using caustic::testing::bearer;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using caustic::testing::WebRtcPeer;
using nlohmann::json;

namespace {

class WebRtc : public ::testing::TestWithParam<const char*> {
 protected:
  static void SetUpTestSuite() { gst_init(nullptr, nullptr); }
};

double mean_abs_difference(const std::vector<guint8>& a, const std::vector<guint8>& b) {
  if (a.size() != b.size() || a.empty()) return -1;
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(int(a[i]) - int(b[i]));
  return sum / a.size();
}

}  // namespace

TEST_P(WebRtc, ViewerReceivesTheStreamAndSeesAPatch) {
  const std::string codec = GetParam();
  ServerProcess server({"--width", "320", "--height", "240", "--framerate", "30"});
  const json s = http("POST", server.url() + "/api/v1/sessions", json{{"scene", "wavy"}, {"codec", codec}}.dump()).json();
  ASSERT_TRUE(s.contains("signal_url")) << s.dump();
  std::string ws = server.url() + s["signal_url"].get<std::string>();
  ws.replace(0, 4, "ws");  // http -> ws
  WebRtcPeer peer(codec, ws);
  ASSERT_TRUE(peer.wait_for_frames(10, 60.0)) << "decoded " << peer.decoded() << "; " << peer.error();
  EXPECT_EQ(peer.width(), 320);
  EXPECT_EQ(peer.height(), 240);
  // No playout delay at the viewer: offered, and asked on every packet.
  EXPECT_NE(peer.offer().find(" http://www.webrtc.org/experiments/rtp-hdrext/playout-delay\r\n"), std::string::npos)
      << peer.offer();
  const int packets = peer.rtp_packets(), zero_delay = peer.zero_playout_delay_packets();
  EXPECT_GT(zero_delay, 0);
  EXPECT_NEAR(zero_delay, packets, 1) << "a packet without the extension, or with a delay";
  const auto before = peer.last_picture();

  const auto auth = bearer(s);
  const auto patched = http("PATCH", server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/params",
                            R"({"light": {"direction": [0.2, 0.1, -1]}})", "application/merge-patch+json", auth);
  ASSERT_EQ(patched.status, 200u) << patched.body;
  EXPECT_GT(peer.frame_messages(), 0) << "no frame message on the data channel";
  EXPECT_EQ(peer.version(), 1u);
  EXPECT_TRUE(peer.wait_for_version(patched.json()["version"], 10.0)) << "version " << peer.version();
  ASSERT_TRUE(peer.wait_for_frames(3, 30.0)) << peer.error();
  EXPECT_GT(mean_abs_difference(before, peer.last_picture()), 1.0) << "the patch did not reach the stream";

  // Still again: the unchanged picture is encoded at the keep-alive rate
  // (still_interval_ms, 1 s), not 30 times a second.
  auto encoded = [&] {
    const std::string text = http("GET", server.url() + "/metrics").body;
    const auto at = text.find("causticd_encode_seconds_count ");
    return at == std::string::npos ? -1L : std::stol(text.substr(at + 30));
  };
  // The patch's previews and full frame, and key frames the peer asked for,
  // may still be on their way on a loaded machine: let them pass first.
  peer.wait_for_frames(1000, 1.5);
  const long encoded_before = encoded();
  peer.wait_for_frames(1000, 4.0);  // plays the stream for 4 s
  const long still_frames = encoded() - encoded_before;
  EXPECT_GE(still_frames, 2);
  // About 4 keep-alive frames, and a few for key frame requests; at the
  // frame rate it would be 120 (30 on a machine loaded to a quarter of it).
  EXPECT_LE(still_frames, 16) << "a still picture was encoded at the frame rate";

  // The server measured what it sent.
  const std::string metrics = http("GET", server.url() + "/metrics").body;
  for (const char* zero : {"causticd_frames_sent_total 0\n", "causticd_encode_seconds_count 0\n",
                           "causticd_frames_rendered_total 0\n"})
    EXPECT_EQ(metrics.find(zero), std::string::npos) << zero;

  // Hanging up ends the session on the server.
  peer.hang_up();
  for (int i = 0; i < 50 && http("GET", server.url() + "/api/v1/health").json()["sessions"] != 0; ++i) g_usleep(100000);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").json()["sessions"], 0);
}

INSTANTIATE_TEST_SUITE_P(Codecs, WebRtc, ::testing::Values("vp8", "h264"));

// The pool's frames tell the viewer the surface they came from, and a drop
// posted to the session shows in a later frame.
TEST(WebRtcWater, FramesCarryTheSurfaceAndShowAPostedDrop) {
  gst_init(nullptr, nullptr);
  ServerProcess server({"--width", "256", "--height", "256", "--framerate", "30"});
  const json s = http("POST", server.url() + "/api/v1/sessions", json{{"scene", "pool"}}.dump()).json();
  ASSERT_TRUE(s.contains("signal_url")) << s.dump();
  std::string ws = server.url() + s["signal_url"].get<std::string>();
  ws.replace(0, 4, "ws");
  WebRtcPeer peer("vp8", ws);
  ASSERT_TRUE(peer.wait_for_frames(5, 60.0)) << peer.error();
  const json water = peer.last_water();
  ASSERT_TRUE(water.is_object()) << "no water in the frame messages";
  ASSERT_EQ(water["n"], 32);
  EXPECT_EQ(water["unit"], 1e-5);
  EXPECT_GT(water["step"].get<std::uint64_t>(), 0u);  // warmed up: rain has fallen
  gsize bytes = 0;
  guchar* heights = g_base64_decode(water["heights"].get<std::string>().c_str(), &bytes);
  EXPECT_EQ(bytes, 2u * 32 * 32);
  int nonzero = 0;
  for (gsize i = 0; i + 1 < bytes; i += 2) nonzero += (heights[i] | heights[i + 1]) != 0;
  g_free(heights);
  EXPECT_GT(nonzero, 100) << "a still surface after rain";
  // The stream moves on by itself.
  const std::uint64_t step = water["step"];
  peer.wait_for_frames(10, 30.0);
  EXPECT_GT(peer.last_water()["step"].get<std::uint64_t>(), step);
  const auto posted = http("POST", server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/drops",
                           R"({"x": 0.2, "y": -0.3, "strength": 0.02})", "application/json", bearer(s));
  ASSERT_EQ(posted.status, 202u) << posted.body;
  const int before = peer.frame_messages();
  EXPECT_TRUE(peer.wait_for_drops(posted.json()["drop"], 30.0));
  std::printf("the drop showed in the %d-th frame message after it was accepted\n", peer.frame_messages() - before);
}

TEST(Signalling, AViewerWhoseCertificateIsNotItsAnswersIsCutOff) {
  // The answer's fingerprint one bit off: webrtcbin took any certificate,
  // so anyone in the media's path could stand in for the viewer.
  gst_init(nullptr, nullptr);
  ServerProcess server;
  const json s = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab"})").json();
  std::string ws = server.url() + s["signal_url"].get<std::string>();
  ws.replace(0, 4, "ws");
  WebRtcPeer peer("vp8", ws);
  peer.edit_answers([](std::string sdp) {
    // "a=fingerprint:sha-256 XX:...": the last hex digit of each line changed.
    for (std::size_t at = sdp.find("a=fingerprint:"); at != std::string::npos; at = sdp.find("a=fingerprint:", at + 1)) {
      char& digit = sdp[sdp.find_first_of("\r\n", at) - 1];
      digit = digit == '0' ? '1' : '0';
    }
    return sdp;
  });
  for (int i = 0; i < 120 && peer.error().find("fingerprint") == std::string::npos; ++i) peer.wait_for_frames(1000, 0.5);
  EXPECT_NE(peer.error().find("the DTLS certificate does not match the answer's fingerprint"), std::string::npos)
      << peer.error();
  int sessions = 1;
  for (int i = 0; i < 50 && sessions > 0; ++i, g_usleep(100000))
    sessions = http("GET", server.url() + "/api/v1/health").json()["sessions"].get<int>();
  EXPECT_EQ(sessions, 0) << "the session outlived a certificate that was not its viewer's";
}

TEST(Signalling, WrongTokenIsRefused) {
  gst_init(nullptr, nullptr);
  ServerProcess server;
  const json s = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab"})").json();
  std::string ws = server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/signal?token=wrong";
  ws.replace(0, 4, "ws");
  WebRtcPeer peer("vp8", ws);
  EXPECT_FALSE(peer.wait_for_frames(1, 3.0));
  EXPECT_EQ(peer.decoded(), 0);
  EXPECT_NE(peer.error().find("did not accept the WebSocket handshake"), std::string::npos) << peer.error();
}
