// SPDX-License-Identifier: LGPL-2.1-or-later
// An answer checked before webrtcbin sees it costs the main loop in
// proportion to its size, however it is shaped. Black-box over loopback.
#include "hardening_support.hpp"
#include "ws_client.hpp"

using namespace caustic::testing;

// Each fmtp parameter of an answer was looked up among all the m-line's
// attributes: a 63 KB answer of 6,400 attributes and an fmtp of 15,500
// parameters held the main loop over a second, and the 64 a socket may
// send before it is cut off over a minute, past the service's watchdog.
// An m-line of more attributes, or an fmtp of more parameters, than any
// browser's answer holds is refused at once, naming what is too many.
TEST(Hardening, AnAnswerTooLargeToCheckCheaplyIsRefused) {
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  std::optional<std::string> m;
  while ((m = ws_read_text(fd, 20000)) && json::parse(*m, nullptr, false).value("type", "") != "offer") {
  }
  ASSERT_TRUE(m) << "no offer";
  const auto answer = [](int attributes, int parameters) {
    std::string fmtp = "a=fmtp:96 q";
    for (int i = 1; i < parameters; ++i) fmtp += ";q";
    std::string sdp = "v=0\n" "o=- 1 1 IN IP4 0.0.0.0\n" "s=-\n" "t=0 0\n" "m=video 9 UDP/TLS/RTP/SAVPF 96\n";
    for (int i = 0; i < attributes; ++i) sdp += "a=z\n";
    return sdp + fmtp + "\nm=application 9 UDP/DTLS/SCTP webrtc-datachannel\n";
  };
  const std::pair<std::string, std::string> cases[] = {
      {answer(6400, 15500), "answer: m-line 0 has more than 256 attributes"},
      {answer(200, 15500), "answer: m-line 0 has an fmtp of more than 64 parameters"},
      {answer(300, 1), "answer: m-line 0 has more than 256 attributes"}};
  for (const auto& [sdp, why] : cases) {
    const std::string message = json{{"type", "answer"}, {"sdp", sdp}}.dump();
    ASSERT_LE(message.size(), 65536u);
    ws_send_frame(fd, 1, true, message);
    std::string error;
    while (error.empty() && (m = ws_read_text(fd, 20000)))
      if (const json j = json::parse(*m, nullptr, false); j.value("type", "") == "error") error = j["message"];
    EXPECT_EQ(error, why);
  }
  EXPECT_EQ(sessions_now(server), 1);
  ::close(fd);
}
