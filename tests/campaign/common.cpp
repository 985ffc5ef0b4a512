// SPDX-License-Identifier: LGPL-2.1-or-later
#include "kinds.hpp"

namespace campaign {

Config base_config() {
  return {{"ice_addresses", "127.0.0.1"},
          {"log_level", "warning"},
          {"width", "256"},
          {"height", "256"},
          {"framerate", "15"},
          {"max_sessions", "8"},
          {"max_sessions_per_address", "4"},
          {"idle_timeout_s", "3"},
          {"viewer_timeout_s", "3"},
          {"max_body_bytes", "1048576"},
          {"max_ws_message_bytes", "65536"},
          {"max_connections", "4096"},
          {"max_connections_per_address", "1024"},
          {"header_timeout_s", "5"},
          {"body_timeout_s", "5"},
          {"connection_idle_timeout_s", "5"},
          {"rate_limit_per_s", "1000"},
          {"rate_limit_burst", "2000"}};
}

void set_key(Config& config, const std::string& key, const std::string& value) {
  for (auto& [k, v] : config)
    if (k == key) {
      v = value;
      return;
    }
  config.emplace_back(key, value);
}

void judge_common(KindReport& report, ServerProcess* server, std::string_view request, const Response& r, bool broken,
                  bool head, bool shed_ok) {
  report.outcome_of(r);
  std::string why;
  if (server) report.check("server process stays alive", server->alive(&why), "  " + why + "\n" + describe(request, r));
  const bool shed = shed_ok && r.kind == Response::Answer && (r.status == 503 || r.status == 429);
  if (r.kind == Response::Answer) {
    report.check("no 5xx answer (503 only as load shedding)", r.status < 500 || (shed && r.status == 503),
                 describe(request, r));
    if (shed) report.check("429/503 carry Retry-After", r.has_header("Retry-After"), describe(request, r));
    const std::string defect = problem_defect(r, head);
    report.check("errors are application/problem+json with type/title/status/detail", defect.empty(),
                 "  " + defect + "\n" + describe(request, r));
    if (r.status != 101) {
      std::string connection = r.header("Connection");
      for (auto& ch : connection) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      report.check("non-WebSocket answers carry Connection: close", connection.find("close") != std::string::npos,
                   describe(request, r));
    }
    if (r.status == 405) report.check("405 carries Allow", r.has_header("Allow"), describe(request, r));
  } else if (r.kind == Response::Closed) {
    report.check("closed without answer only for broken HTTP", broken, describe(request, r));
  } else if (r.kind == Response::Timeout) {
    report.check("every request is answered or closed in time", false, describe(request, r));
  } else if (r.kind == Response::Garbage) {
    report.check("answers are well-formed HTTP", false, describe(request, r));
  } else {
    report.check("connections are accepted", shed_ok, describe(request, r));
  }
}

Session create_session(int port, const std::string& scene, Response* answer, const std::string& source) {
  const std::string body = nlohmann::json{{"scene", scene}}.dump();
  const Response r =
      exchange(port, make_request("POST", "/api/v1/sessions", {{"Content-Type", "application/json"}}, body), 30000,
               false, false, source);
  if (answer) *answer = r;
  Session s;
  if (r.kind != Response::Answer || r.status != 201) return s;
  const auto j = nlohmann::json::parse(r.body, nullptr, false);
  if (j.is_object() && j.contains("id") && j["id"].is_string() && j.contains("token") && j["token"].is_string()) {
    s.id = j["id"];
    s.token = j["token"];
  }
  return s;
}

bool delete_session(int port, const Session& s) {
  const Response r = exchange(
      port, make_request("DELETE", "/api/v1/sessions/" + s.id, {{"Authorization", "Bearer " + s.token}}), 10000);
  return r.kind == Response::Answer && r.status == 204;
}

std::vector<std::string> scene_ids(int port) {
  std::vector<std::string> ids;
  const auto j = nlohmann::json::parse(fetch_body(port, "/api/v1/scenes"), nullptr, false);
  if (!j.is_object() || !j.contains("scenes") || !j["scenes"].is_array()) return ids;
  for (const auto& s : j["scenes"])
    if (s.is_object() && s.contains("id") && s["id"].is_string()) ids.push_back(s["id"]);
  return ids;
}

Conn open_signal(int port, const Session& s, std::mt19937& rng, Response* answer) {
  Conn c = connect_loopback(port);
  if (!c.ok()) return c;
  send_all(c, ws_handshake("/api/v1/sessions/" + s.id + "/signal?token=" + s.token, rng));
  const Response r = read_response(c, 10000);
  if (answer) *answer = r;
  if (r.kind != Response::Answer || r.status != 101) return Conn();
  return c;
}

}  // namespace campaign
