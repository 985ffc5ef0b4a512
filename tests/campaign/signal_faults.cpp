// SPDX-License-Identifier: LGPL-2.1-or-later
#include "signal_faults.hpp"

#include <thread>

namespace campaign {

namespace {

enum class Reply { Error, CloseFrame, Closed, Nothing };

const char* reply_name(Reply r) {
  switch (r) {
    case Reply::Error:
      return "ws error message";
    case Reply::CloseFrame:
      return "ws close frame";
    case Reply::Closed:
      return "ws closed";
    case Reply::Nothing:
      return "ws no reply";
  }
  return "?";
}

// Reads frames until the server reacts to what we sent: offers and ICE
// candidates it sends on its own are skipped. `pong`: a pong counts too.
Reply await_reply(Conn& ws, int timeout_ms, bool pong = false, int* close_code = nullptr) {
  const auto start = Clock::now();
  while (ms_since(start) < timeout_ms) {
    const WsFrame f = ws_read(ws, timeout_ms - static_cast<int>(ms_since(start)));
    if (!f.ok) return f.timeout ? Reply::Nothing : Reply::Closed;
    if (f.opcode == 8) {
      if (close_code && f.payload.size() >= 2)
        *close_code = (static_cast<unsigned char>(f.payload[0]) << 8) | static_cast<unsigned char>(f.payload[1]);
      return Reply::CloseFrame;
    }
    if (f.opcode == 10 && pong) return Reply::Error;
    if (f.opcode == 1) {
      const auto j = nlohmann::json::parse(f.payload, nullptr, false);
      if (j.is_object() && j.value("type", "") == "error") return Reply::Error;
      if (j.is_object() && j.value("type", "") == "bye") return Reply::CloseFrame;
    }
  }
  return Reply::Nothing;
}

struct Fault {
  std::string name;
  std::vector<std::string> frames;  // sent in order
  bool must_close = false;          // a protocol violation or a message over the limit
  bool pong = false;
};

Fault make_fault(int which, std::mt19937& rng, size_t limit) {
  auto text = [&](const std::string& s, bool fin = true) { return ws_frame(1, s, fin, rng); };
  switch (which) {
    case 0:
      return {"invalid JSON", {text("{not json")}};
    case 1:
      return {"unknown type", {text("{\"type\":\"hello\"}")}};
    case 2:
      return {"array message", {text("[1,2,3]")}};
    case 3:
      return {"type not a string", {text("{\"type\":1}")}};
    case 4:
      return {"answer with bad SDP", {text("{\"type\":\"answer\",\"sdp\":\"garbage\"}")}};
    case 5:
      return {"ice out of range", {text("{\"type\":\"ice\",\"candidate\":\"\\u0001\",\"sdpMLineIndex\":99}")}};
    case 6:
      return {"deep nesting", {text(std::string(50000, '[') + std::string(50000, ']'))}, false};
    case 7:
      return {"message over the limit", {text("{\"type\":\"" + std::string(limit * 2, 'x') + "\"}")}, true};
    case 8: {
      Fault f{"fragmented message over the limit", {}, true};
      const size_t piece = 16384;
      f.frames.push_back(ws_frame(1, "{\"type\":\"" + std::string(piece, 'y'), false, rng));
      for (size_t sent = piece; sent < limit * 2; sent += piece)
        f.frames.push_back(ws_frame(0, std::string(piece, 'y'), false, rng));
      f.frames.push_back(ws_frame(0, "\"}", true, rng));
      return f;
    }
    case 9:
      return {
          "fragmented unknown type",
          {ws_frame(1, "{\"type\"", false, rng), ws_frame(0, ":\"hel", false, rng), ws_frame(0, "lo\"}", true, rng)}};
    case 10:
      return {"binary frame", {ws_frame(2, "\x00\x01\x02", true, rng)}};
    case 11:
      return {"invalid UTF-8 text", {text("{\"type\":\"\xff\xfe\"}")}, true};
    case 12:
      return {"unmasked client frame", {ws_frame(1, "{\"type\":\"ping\"}", true, rng, false)}, true};
    case 13:
      return {"reserved opcode", {ws_frame(3, "x", true, rng)}, true};
    case 14:
      return {"continuation without start", {ws_frame(0, "x", true, rng)}, true};
    case 15:
      return {"ping control frame", {ws_frame(9, "hi", true, rng)}, false, true};
    default:
      return {"oversized control frame", {ws_frame(9, std::string(200, 'p'), true, rng)}, true};
  }
}

}  // namespace

void run_signal_faults(const Options& opt, KindReport& rep, ServerProcess& server, const std::string& scene) {
  std::mt19937 rng(opt.seed + 7);
  const int port = server.port();
  const size_t limit = 65536;  // max_ws_message_bytes of base_config()
  const int total = opt.short_mode ? 30 : 250;
  const double budget_ms = opt.short_mode ? 25000 : 120000;
  Session session;
  Conn ws;
  int sent = 0;
  const auto start = Clock::now();
  for (int i = 0; i < total && ms_since(start) < budget_ms; ++i) {
    if (!ws.ok()) {
      Response answer;
      session = create_session(port, scene, &answer);
      if (!rep.check("a session for signalling faults can be created", session.ok(),
                     describe("POST /api/v1/sessions", answer)))
        break;
      ws = open_signal(port, session, rng, &answer);
      if (!rep.check("the signalling socket opens with the right token", ws.ok(), describe("GET .../signal", answer))) {
        delete_session(port, session);
        break;
      }
    }
    const Fault f = make_fault(static_cast<int>(rng() % 17), rng, limit);
    bool send_ok = true;
    for (const auto& frame : f.frames) send_ok = send_ok && send_all(ws, frame, 3000);
    int code = 0;
    const Reply reply = await_reply(ws, 2000, f.pong, &code);
    ++sent;
    rep.outcome(reply_name(reply));
    std::string why;
    const std::string shown = "  signalling fault: " + f.name + " -> " + reply_name(reply) +
                              (code ? " (close code " + std::to_string(code) + ")" : "") +
                              (send_ok ? "" : ", send cut short");
    rep.check("server process stays alive", server.alive(&why), shown + "; " + why);
    if (!server.alive()) return;
    if (f.must_close)
      rep.check("protocol violations and messages over max_ws_message_bytes close the socket",
                reply == Reply::CloseFrame || reply == Reply::Closed, shown);
    else
      rep.check("a bad signalling message gets an error message (socket may stay)", reply != Reply::Nothing, shown);
    if (reply == Reply::CloseFrame || reply == Reply::Closed) {
      ws.close();
      // Closing the socket ends the session (docs/api.md).
      int status = 0;
      const auto closed_at = Clock::now();
      while (ms_since(closed_at) < 3000) {
        fetch_body(port, "/api/v1/sessions/" + session.id + "/params", session.token, &status);
        if (status != 200) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      rep.check("a closed signalling socket ends its session within 3 s", status != 200, shown);
      delete_session(port, session);
    }
  }
  rep.figure("signalling_faults", sent);
  if (ws.ok()) {
    ws.close();
    delete_session(port, session);
  }
}

}  // namespace campaign
