// SPDX-License-Identifier: LGPL-2.1-or-later
// Hardening of sessions: how many an address may hold, a token to create
// them, viewers that must show signs of life, and a viewer that reconnects.
// Each failed against the server before its fix. Black-box over loopback.
#include "hardening_support.hpp"
#include "sdp_edit.hpp"
#include "ws_client.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

using namespace caustic::testing;

namespace {

// Reads the socket's messages until an offer comes (false: none within 20 s
// of the last message).
bool read_until_offer(int fd) {
  std::optional<std::string> message;
  while ((message = ws_read_text(fd, 20000)))
    if (json::parse(*message, nullptr, false).value("type", "") == "offer") return true;
  return false;
}

}  // namespace

TEST(Hardening, SessionsPerAddressAreLimited) {
  ServerProcess server({"--set", "max_sessions_per_address=1", "--max-sessions", "4"});
  create_session(server);
  const Response r = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab"})");
  EXPECT_EQ(r.status, 429u) << r.body;
  EXPECT_EQ(r.content_type, "application/problem+json");
  EXPECT_EQ(sessions_now(server), 1);
}

TEST(Hardening, SessionCreationCanRequireAToken) {
  const std::string token = "0123456789abcdef0123";
  ServerProcess server({"--set", "session_create_token=" + token});
  const std::string url = server.url() + "/api/v1/sessions";
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})").status, 401u);
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})", "application/json", {{"Authorization", "Bearer nope"}}).status,
            401u);
  // The scheme's case does not matter (RFC 9110 11.1).
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})", "application/json", {{"Authorization", "bearer " + token}}).status,
            201u);
}

TEST(Hardening, ASilentViewerLosesItsSession) {
  ServerProcess server({"--set", "viewer_timeout_s=2"});
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  // It takes the offer and then says nothing: no answer, no RTCP, no ping.
  ASSERT_TRUE(ws_read_text(fd, 20000).has_value());
  EXPECT_TRUE(wait_sessions(server, 0, 2 + 5 + 5)) << "a silent viewer still holds its session";
  ::close(fd);
}

TEST(Hardening, AViewerThatPingsKeepsItsSession) {
  ServerProcess server({"--set", "viewer_timeout_s=2"});
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  for (int i = 0; i < 8; ++i) {  // 4 s, twice the timeout
    ws_send_frame(fd, 1, true, R"({"type": "ping"})");
    g_usleep(500000);
  }
  EXPECT_EQ(sessions_now(server), 1);
  ::close(fd);
}

TEST(Hardening, ASecondSignallingSocketGetsAFreshOffer) {
  ServerProcess server;
  const json s = create_session(server);
  const int first = ws_open(server.port(), signal_path(s));
  ASSERT_GE(first, 0);
  const auto offer1 = ws_read_text(first, 20000);
  ASSERT_TRUE(offer1.has_value());
  EXPECT_EQ(json::parse(*offer1)["type"], "offer");
  const int second = ws_open(server.port(), signal_path(s));
  ASSERT_GE(second, 0);
  EXPECT_TRUE(read_until_offer(second)) << "a reconnecting viewer got no offer";
  ::close(first);
  ::close(second);
}

TEST(Hardening, AViewerThatReconnectsAtOnceGetsOneOfferTheNewPipelines) {
  // The first pipeline's offer, made on webrtcbin's thread while the second
  // socket replaces the first, once reached the new viewer too: two offers,
  // the first for a webrtcbin that was gone. Bounded: four sessions, each
  // read for a few seconds.
  ServerProcess server;
  for (int round = 0; round < 4; ++round) {
    const json s = create_session(server);
    const int first = ws_open(server.port(), signal_path(s));
    const int second = ws_open(server.port(), signal_path(s));
    ASSERT_GE(first, 0);
    ASSERT_GE(second, 0);
    int offers = 0;
    for (std::optional<std::string> message; (message = ws_read_text(second, offers == 0 ? 20000 : 3000));)
      offers += json::parse(*message, nullptr, false).value("type", "") == "offer";
    EXPECT_EQ(offers, 1) << "round " << round;
    ::close(first);
    ::close(second);
  }
}

TEST(Hardening, RebuildingAStreamForNewSocketsIsLimited) {
  // Each socket that replaces a session's viewer rebuilds its stream: a
  // loop of them once cost a pipeline each, as fast as the client asked.
  // A burst of 3 sockets goes through (the first and two that replace
  // it), then one every 2 s; the tally allows for the time a slow machine
  // takes. Bounded: 12 sockets, or 60 s.
  ServerProcess server;
  const json s = create_session(server);
  int viewer = ws_open(server.port(), signal_path(s));
  ASSERT_GE(viewer, 0);
  const auto start = std::chrono::steady_clock::now();
  int replaced = 0;
  std::string refusal;
  for (int k = 0; k < 12 && std::chrono::steady_clock::now() - start < std::chrono::seconds(60); ++k) {
    const int next = ws_open(server.port(), signal_path(s), &refusal);
    if (next < 0) break;
    ::close(viewer);
    viewer = next;
    ++replaced;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(raw_status(refusal), 429) << "after " << replaced << " replacements in " << seconds << " s: " << refusal;
  EXPECT_GE(replaced, 2);
  EXPECT_LE(replaced, 2 + static_cast<int>(std::ceil(0.5 * seconds)));
  EXPECT_GE(std::stoi(raw_header(refusal, "Retry-After")), 1);
  EXPECT_EQ(raw_header(refusal, "Content-Type"), "application/problem+json");
  // The refusal left the session and its viewer as they were.
  EXPECT_EQ(sessions_now(server), 1);
  EXPECT_TRUE(read_until_offer(viewer));
  ::close(viewer);
}

// Answers a browser could not give but a client can write, each of which
// webrtcbin once answered by aborting the whole server: the offer's text
// turned round as an answer (recvonly, setup active), then its two m-line
// sections swapped, its BUNDLE group tagged by the data channel, its mids
// traded between the m-lines, or the video's ICE ufrag given twice at the
// session level instead.
std::vector<std::string> unfitting_answers(const std::string& offer) {
  const std::string answer = replaced(replaced(offer, "a=setup:actpass", "a=setup:active"), "a=sendonly", "a=recvonly");
  const std::size_t first = answer.find("m="), second = answer.find("\r\nm=", first) + 2;
  const std::size_t third = answer.find("\r\nm=", second);
  const std::size_t end = third == std::string::npos ? answer.size() : third + 2;
  const std::string swapped = answer.substr(0, first) + answer.substr(second, end - second) +
                              answer.substr(first, second - first) + answer.substr(end);
  const std::string tagged = replaced(answer, "a=group:BUNDLE video0 application1", "a=group:BUNDLE application1 video0");
  const std::string traded = replaced(
      replaced(replaced(answer, "a=mid:video0", "a=mid:x"), "a=mid:application1", "a=mid:video0"), "a=mid:x",
      "a=mid:application1");
  // The video's ufrag moved to the session level, twice over.
  std::string credentials = answer;
  const std::size_t ufrag = credentials.find("a=ice-ufrag:", credentials.find("m=video"));
  credentials.erase(ufrag, credentials.find("\r\n", ufrag) + 2 - ufrag);
  credentials.insert(first, "a=ice-ufrag:aaaaaaaa\r\na=ice-ufrag:bbbbbbbb\r\n");
  return {swapped, tagged, traded, credentials};
}

TEST(Hardening, AnAnswerWhoseMLinesDoNotFitTheOfferIsRefused) {
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  std::string offer;
  for (std::optional<std::string> m; offer.empty() && (m = ws_read_text(fd, 20000));)
    if (const json j = json::parse(*m, nullptr, false); j.value("type", "") == "offer") offer = j["sdp"];
  ASSERT_NE(offer.find("a=group:BUNDLE video0 application1"), std::string::npos) << "webrtcbin's offer: " << offer;
  ASSERT_NE(offer.find("a=mid:application1"), std::string::npos) << offer;
  const char* reasons[] = {"m-line 0 must answer the offer's video m-line", "a BUNDLE group must start with",
                           "m-line 0 must keep the offer's mid", "at most one session-level a=ice-ufrag"};
  const std::vector<std::string> answers = unfitting_answers(offer);
  for (std::size_t k = 0; k < answers.size(); ++k) {
    ws_send_frame(fd, 1, true, json{{"type", "answer"}, {"sdp", answers[k]}}.dump());
    std::string error;
    for (std::optional<std::string> m; error.empty() && (m = ws_read_text(fd, 20000));)
      if (const json j = json::parse(*m, nullptr, false); j.value("type", "") == "error") error = j["message"];
    EXPECT_NE(error.find(reasons[k]), std::string::npos) << error;
    ASSERT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u) << "the server went down at answer " << k;
  }
  EXPECT_EQ(sessions_now(server), 1);
  ::close(fd);
}

TEST(Hardening, TheViewersCandidatesAreBoundedInSizeNumberAndMLine) {
  // webrtcbin keeps every candidate it is given until the next negotiation
  // (one for an m-line it has no transport for, or before the answer): a
  // viewer looping 60 KB candidates grew the server without bound.
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(read_until_offer(fd));
  std::optional<std::string> message;
  const auto candidate = [](int n, const std::string& extra = "") {
    return "candidate:" + std::to_string(n) + " 1 udp 2122260223 127.0.0.1 " + std::to_string(40000 + n) + " typ host" +
           extra;
  };
  const auto send_ice = [&](const std::string& c, int mline) {
    ws_send_frame(fd, 1, true, json{{"type", "ice"}, {"candidate", c}, {"sdpMLineIndex", mline}}.dump());
  };
  send_ice(candidate(1, " x " + std::string(600, 'a')), 0);  // too long
  send_ice(candidate(2), 7);                                 // no such m-line
  // Fields libnice dropped without a word, or wrapped to another port.
  const std::vector<std::pair<std::string, std::string>> unreadable = {
      {"candidate:3 1 udp 2122260223 example.com 40003 typ host", "address must be an IP address or an mDNS name"},
      {"candidate:4 1 udp 2122260223 127.0.0.1 99999 typ host", "port must be in [0, 65535]"},
      {"candidate:5 1 udp 2122260223 127.0.0.1 40005 typ nearby", "type must be host, srflx, prflx or relay"},
      {"candidate:6 1 udp 99999999999 127.0.0.1 40006 typ host", "priority must be in [1, 2^32 - 1]"},
      {"candidate:7 1 udp 2122260223 127.0.0.1 40007 typ srflx raddr nowhere rport 9", "raddr must be an IP address"}};
  for (const auto& [c, why] : unreadable) send_ice(c, 0);
  for (int i = 0; i < 70; ++i) send_ice(candidate(100 + i), 0);
  std::vector<std::string> errors;
  while ((message = ws_read_text(fd, 3000)))
    if (const json m = json::parse(*message, nullptr, false); m.value("type", "") == "error")
      errors.push_back(m.value("message", ""));
  ASSERT_EQ(errors.size(), 3u + unreadable.size()) << ::testing::PrintToString(errors);
  EXPECT_EQ(errors[0], "ice: a candidate is at most 512 characters");
  EXPECT_EQ(errors[1], "ice: the offer has 2 m-lines");
  for (std::size_t i = 0; i < unreadable.size(); ++i)
    EXPECT_NE(errors[2 + i].find(unreadable[i].second), std::string::npos) << errors[2 + i];
  EXPECT_EQ(errors.back(), "ice: at most 64 candidates a connection");
  EXPECT_EQ(sessions_now(server), 1);
  ::close(fd);
}

TEST(Hardening, AViewerFloodingUnusableMessagesIsCutOffNotAnsweredForEver) {
  // Each unusable message was answered with an error that libsoup queued
  // for a peer that read nothing: 10 MB of 7-byte messages held 300 MB.
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(read_until_offer(fd));
  // 200 frames: within what the socket may send at once (the test below).
  for (int i = 0; i < 199; ++i) ws_send_frame(fd, 1, true, i % 2 ? "x" : R"({"type": "nope"})");
  ws_send_frame(fd, 2, true, "binary");
  int errors = 0;
  std::string bye;
  for (std::optional<std::string> message; (message = ws_read_text(fd, 20000));) {
    const json m = json::parse(*message, nullptr, false);
    if (m.value("type", "") == "error") ++errors;
    if (m.value("type", "") == "bye") bye = m.value("reason", "");
  }
  ::close(fd);
  EXPECT_EQ(errors, 64) << "each unusable message up to the limit is answered, and no more";
  EXPECT_EQ(bye, "more than 64 signalling messages the server cannot use");
  EXPECT_TRUE(wait_sessions(server, 0, 20));
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Hardening, ASignallingSocketThatNeverStopsSendingIsCutOff) {
  // libsoup reads a socket until it would block: a client sending pings
  // without pause kept the main loop, and every other client, waiting.
  ServerProcess server;
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(read_until_offer(fd));
  for (int i = 0; i < 2000; ++i) ws_send_frame(fd, 1, true, R"({"type": "ping"})");
  bool closed = false;
  const WsGoodbye goodbye = ws_goodbye(raw_read_all(fd, 20000, &closed));
  ::close(fd);
  EXPECT_TRUE(closed) << "the server took 2000 frames at once";
  EXPECT_EQ(goodbye.code, 1008u) << "cut off without a close frame saying why";
  EXPECT_EQ(goodbye.reason, "more WebSocket frames than a signalling socket takes");
  EXPECT_EQ(goodbye.bye, goodbye.reason);
  EXPECT_TRUE(wait_sessions(server, 0, 20));
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").status, 200u);
}

TEST(Hardening, ASignallingMessageUpToTheConfiguredLimitIsTaken) {
  // The socket's own limit was a fixed 64 KiB: a larger max_ws_message_bytes
  // let the message past the accept path only for libsoup to cut it off.
  ServerProcess server({"--set", "max_ws_message_bytes=131072"});
  const json s = create_session(server);
  const int fd = ws_open(server.port(), signal_path(s));
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(read_until_offer(fd));
  ws_send_frame(fd, 1, true, json{{"type", "ping"}, {"pad", std::string(100000, 'a')}}.dump());
  ws_send_frame(fd, 1, true, "x");  // answered only while the socket is open
  std::string error;
  for (std::optional<std::string> m; error.empty() && (m = ws_read_text(fd, 20000));)
    if (const json j = json::parse(*m, nullptr, false); j.value("type", "") == "error") error = j.value("message", "");
  EXPECT_EQ(error, "a signalling message is a JSON object with a string \"type\"");
  EXPECT_EQ(sessions_now(server), 1);
  ::close(fd);
}

TEST(Hardening, SignallingSocketsAreNotCompressed) {
  // With permessage-deflate, 48 KB on the wire, within the message limit,
  // inflated to 50 MB in the server before any limit saw it.
  ServerProcess server;
  const json s = create_session(server);
  const int fd = raw_connect(server.port());
  ASSERT_GE(fd, 0);
  raw_send(fd, request_text("GET", signal_path(s),
                            "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
                            "Sec-WebSocket-Extensions: permessage-deflate; client_max_window_bits\r\n"));
  std::string head;
  char ch;
  while (head.find("\r\n\r\n") == std::string::npos && head.size() < 4096) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 20000) <= 0 || ::recv(fd, &ch, 1, 0) != 1) break;
    head += ch;
  }
  ASSERT_EQ(raw_status(head), 101) << head;
  EXPECT_EQ(raw_header(head, "Sec-WebSocket-Extensions"), "") << head;
  // One Connection field, the upgrade's: every plain answer's "close" stood
  // beside it and contradicted the 101.
  EXPECT_EQ(raw_header(head, "Connection"), "Upgrade") << head;
  EXPECT_EQ(head.find("close"), std::string::npos) << head;
  // A frame marked compressed (RSV1) is then a protocol error, not inflated.
  const std::string stored = std::string("\x00\x01\x00\xfe\xff", 5) + "x";  // a deflate stored block
  std::string frame = "\xc1";
  frame += static_cast<char>(0x80 | stored.size());
  frame += std::string(4, '\0');  // a zero mask
  raw_send(fd, frame + stored);
  bool closed = false;
  raw_read_all(fd, 20000, &closed);
  ::close(fd);
  EXPECT_TRUE(closed) << "a compressed frame was taken";
  EXPECT_TRUE(wait_sessions(server, 0, 20));
}

TEST(Hardening, APipelineFileWithoutItsNamedElementsFailsItsSessionsNotTheServer) {
  // The operator's copy of the data folder, its VP8 pipeline without the
  // encoder's name (the frame probes reach it by name): the server ran with
  // G_DEBUG=fatal-criticals and died at the first session.
  const std::filesystem::path data = std::filesystem::path(CAUSTICD_BINARY).parent_path().parent_path() / "share/causticd";
  char pattern[] = "/tmp/causticd-data-XXXXXX";
  ASSERT_NE(::mkdtemp(pattern), nullptr);
  const std::filesystem::path copy = pattern;
  struct Gone {  // also when an assertion returns early
    std::filesystem::path path;
    ~Gone() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  } gone{copy};
  std::filesystem::create_symlink(data / "assets", copy / "assets");
  std::filesystem::create_symlink(data / "web", copy / "web");
  std::filesystem::create_directory(copy / "pipelines");
  std::filesystem::copy_file(data / "pipelines/h264.pipeline", copy / "pipelines/h264.pipeline");
  // The copy of `codec`'s pipeline with its encoder's name taken away.
  const auto unname_encoder = [&](const std::string& codec, const std::filesystem::path& from, const std::string& encoder) {
    std::ifstream in(from / "pipelines" / (codec + ".pipeline"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t named = text.find(encoder + " name=encoder");
    if (named == std::string::npos) return false;
    text.replace(named, encoder.size() + std::string(" name=encoder").size(), encoder);
    std::ofstream(copy / "pipelines" / (codec + ".pipeline")) << text;
    return true;
  };
  ASSERT_TRUE(unname_encoder("vp8", data, "vp8enc"));
  {
    ServerProcess server({}, {{"CAUSTICD_DATA_DIR", copy.string()}});
    const Response r = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab", "codec": "vp8"})");
    EXPECT_EQ(r.status, 500u) << r.body;
    EXPECT_EQ(r.content_type, "application/problem+json");
    EXPECT_EQ(sessions_now(server), 0);
    // The other codec's file is whole: its sessions start.
    const Response h264 = http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab", "codec": "h264"})");
    ASSERT_EQ(h264.status, 201u) << h264.body;
    const int fd = ws_open(server.port(), signal_path(h264.json()));
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(read_until_offer(fd));
    // Broken in turn while the session runs: a viewer coming back rebuilds
    // the pipeline, which now fails, and the session ends at once rather
    // than hold its slot with no stream until the idle reclaim.
    ASSERT_TRUE(unname_encoder("h264", copy, "x264enc"));
    const int again = ws_open(server.port(), signal_path(h264.json()));
    EXPECT_TRUE(wait_sessions(server, 0, 10)) << "the session outlived its failed rebuild";
    if (again >= 0) ::close(again);
    ::close(fd);
  }
}
