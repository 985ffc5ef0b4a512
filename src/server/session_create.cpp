// SPDX-License-Identifier: LGPL-2.1-or-later
// POST /api/v1/sessions: the checks every new session passes (body, scene,
// codec, mode, room, the client's share), then a one-viewer session here
// or a broadcast through Janus (broadcast.cpp).
#include "caustic/json_text.hpp"
#include "http_util.hpp"
#include "log.hpp"
#include "server_state.hpp"

namespace caustic::server {

// Parses a JSON object body, answering 415/413/400 itself on failure.
bool read_json_body(ServerState& s, SoupServerMessage* msg, std::initializer_list<const char*> types,
                    nlohmann::json* out) {
  SoupMessageHeaders* headers = soup_server_message_get_request_headers(msg);
  GHashTable* params = nullptr;
  const char* type = soup_message_headers_get_content_type(headers, &params);
  // JSON is UTF-8 (RFC 8259 8.1): a body said to be in another charset
  // would be read as something it is not.
  const char* charset = params ? static_cast<const char*>(g_hash_table_lookup(params, "charset")) : nullptr;
  const bool utf8 = !charset || g_ascii_strcasecmp(charset, "utf-8") == 0 || g_ascii_strcasecmp(charset, "utf8") == 0;
  if (params) g_hash_table_destroy(params);
  bool accepted = false;
  for (const char* t : types) accepted = accepted || (type && g_ascii_strcasecmp(type, t) == 0);
  if (!accepted || !utf8) {
    std::string list;
    for (const char* t : types) list += (list.empty() ? "" : " or ") + std::string(t);
    // A PATCH refused for its media type says which it takes (RFC 5789 2.2).
    if (g_strcmp0(soup_server_message_get_method(msg), "PATCH") == 0) {
      std::string accept;
      for (const char* t : types) accept += (accept.empty() ? "" : ", ") + std::string(t);
      soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Accept-Patch", accept.c_str());
    }
    reply_problem(msg, s.metrics, SOUP_STATUS_UNSUPPORTED_MEDIA_TYPE,
                  accepted ? "the body must be UTF-8, as JSON is" : "the body must be " + list);
    return false;
  }
  SoupMessageBody* body = soup_server_message_get_request_body(msg);
  // The accept path refused longer bodies before they were read; this
  // guards a body that arrives some other way.
  if (body->length > static_cast<goffset>(s.config.max_body_bytes)) {
    reply_problem(msg, s.metrics, SOUP_STATUS_REQUEST_ENTITY_TOO_LARGE,
                  "the body is larger than " + std::to_string(s.config.max_body_bytes) + " bytes");
    return false;
  }
  JsonTextError error;
  auto parsed = parse_json_text(std::string_view(body->data, static_cast<std::size_t>(body->length)), &error);
  if (!parsed) {
    reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST,
                  "the body is not JSON: " +
                      where_json_broke(std::string_view(body->data, static_cast<std::size_t>(body->length)), error));
    return false;
  }
  if (!parsed->is_object()) {
    reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST, "the body must be a JSON object");
    return false;
  }
  *out = std::move(*parsed);
  return true;
}

void create_session(ServerState& s, SoupServerMessage* msg) {
  if (!s.config.session_create_token.empty() && !same_secret(bearer_token(msg), s.config.session_create_token)) {
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "WWW-Authenticate", "Bearer");
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNAUTHORIZED, "creating a session needs this server's bearer token");
  }
  nlohmann::json body;
  if (!read_json_body(s, msg, {"application/json"}, &body)) return;
  for (const auto& [key, value] : body.items())
    if (key != "scene" && key != "codec" && key != "mode")
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, printable_name(key) + ": unknown key",
                           printable_name(key));
  if (!body.contains("scene") || !body["scene"].is_string())
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, "scene: must be a scene id (string)",
                         "scene");
  const std::string scene_id = body["scene"];
  bool loading = false;
  const auto entry = s.find_scene(scene_id, &loading);
  if (loading) {
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After", "2");
    return reply_problem(msg, s.metrics, SOUP_STATUS_SERVICE_UNAVAILABLE, "the design is being loaded; retry in a moment");
  }
  if (!entry)
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, "scene: no such scene", "scene");
  std::string codec = s.config.codec;
  if (body.contains("codec")) {
    if (!body["codec"].is_string() || (body["codec"] != "vp8" && body["codec"] != "h264"))
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, "codec: must be \"vp8\" or \"h264\"",
                           "codec");
    codec = body["codec"];
  }
  bool broadcast = false;
  if (body.contains("mode")) {
    if (!body["mode"].is_string() || (body["mode"] != "viewer" && body["mode"] != "broadcast"))
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY,
                           "mode: must be \"viewer\" (one viewer, WebRTC) or \"broadcast\" (many, through Janus)",
                           "mode");
    broadcast = body["mode"] == "broadcast";
    if (broadcast && !s.janus)
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY,
                           "mode: this server has no broadcast server configured (janus_admin_url)", "mode");
  }
  if (s.draining) {
    ++s.metrics.sessions_rejected;
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After", "5");
    return reply_problem(msg, s.metrics, SOUP_STATUS_SERVICE_UNAVAILABLE,
                         "this instance is stopping and takes no new sessions");
  }
  if (s.sessions_taken() >= s.config.max_sessions) {
    ++s.metrics.sessions_rejected;
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After", "10");
    return reply_problem(msg, s.metrics, SOUP_STATUS_SERVICE_UNAVAILABLE,
                         "the server is full (" + std::to_string(s.config.max_sessions) + " sessions)");
  }
  const std::string address = client_address(msg, s.config.trusted_proxies);
  if (const int held = s.sessions_held_by(address); held >= s.config.max_sessions_per_address) {
    ++s.metrics.sessions_rejected;
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After", "10");
    return reply_problem(msg, s.metrics, 429,
                         "your address holds " + std::to_string(held) + " sessions already (the limit); end one first");
  }
  if (broadcast) return create_broadcast(s, msg, entry, codec, address);
  const std::string id = random_hex();
  ServerState* state = &s;
  SessionOptions options{codec, address, &s.config, s.data_dir, &s.metrics,
                         [state](const std::string& sid, const std::string& why) { state->end_session(sid, why); },
                         std::nullopt};
  std::shared_ptr<Session> session;
  try {
    session = Session::start(id, entry, options);
  } catch (const std::exception& e) {
    log(Level::error, std::string("cannot start a session: ") + e.what(), {id, scene_id, codec, address});
    return reply_problem(msg, s.metrics, SOUP_STATUS_INTERNAL_SERVER_ERROR, "the stream could not be started");
  }
  s.sessions[id] = session;
  ++s.metrics.sessions_created;
  log(Level::info, "session " + id + " started: scene " + scene_id + ", " + codec, session->log_context());
  // Every later request of the session names this instance (instance.hpp).
  const std::string url = url_prefix(s.config) + "/api/v1/sessions/" + id;
  const std::string signal = url + "/signal?token=" + session->token();
  soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Location", url.c_str());
  reply_json(msg, SOUP_STATUS_CREATED,
             {{"id", id}, {"token", session->token()}, {"codec", codec}, {"url", url}, {"signal_url", signal},
              {"params", public_params(*session)}});
}

}  // namespace caustic::server
