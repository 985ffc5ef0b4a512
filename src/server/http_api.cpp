// The REST API of docs/api.md (openapi.yaml).
#include "http_util.hpp"
#include "log.hpp"
#include "server_state.hpp"
#include "static_files.hpp"

#include <regex>

namespace caustic::server {
namespace {

// Keys a session's viewer may not patch: the mesh and the gallery text
// belong to the scene, the size to the negotiated stream.
const char* const kFixedKeys[][2] = {{"mesh", nullptr},     {"name", nullptr},   {"description", nullptr},
                                     {"render", "width"},   {"render", "height"}};

nlohmann::json public_params(Session& session) {
  const ParamStore::Snapshot snap = session.params().snapshot();
  nlohmann::json params = scene_to_json(snap.scene);
  params.erase("mesh");  // a protected mesh is not even named
  return {{"version", snap.version}, {"params", params}, {"fidelity", fidelity_of(session.entry(), snap.scene)}};
}

struct Route {
  std::string session;  // id, when the path names one
  std::string rest;     // what follows /api/v1/sessions/{id}
};

std::string method_of(SoupServerMessage* msg) { return soup_server_message_get_method(msg); }

// Browsers cannot set headers on a WebSocket: its token travels in the query.
std::string query_token(SoupServerMessage* msg) {
  std::string token;
  if (const char* query = g_uri_get_query(soup_server_message_get_uri(msg))) {
    GHashTable* form = soup_form_decode(query);
    if (const char* t = static_cast<const char*>(g_hash_table_lookup(form, "token"))) token = t;
    g_hash_table_unref(form);
  }
  return token;
}

void health(ServerState& s, SoupServerMessage* msg) {
  reply_json(msg, SOUP_STATUS_OK,
             {{"status", "ok"}, {"version", CAUSTICD_VERSION}, {"sessions", s.sessions.size()},
              {"max_sessions", s.config.max_sessions}, {"renderer", s.renderer}});
}

void scenes(ServerState& s, SoupServerMessage* msg) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [id, entry] : s.gallery->entries) list.push_back(describe(*entry));
  reply_json(msg, SOUP_STATUS_OK, {{"scenes", list}});
}

void thumbnail(ServerState& s, SoupServerMessage* msg, const std::string& id) {
  auto it = s.gallery->entries.find(id);
  if (it == s.gallery->entries.end()) return reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such scene");
  const auto& png = it->second->thumbnail_png;
  reply_bytes(msg, SOUP_STATUS_OK, "image/png", png.data(), png.size());
}

// Parses a JSON object body, answering 415/413/400 itself on failure.
bool read_json_body(ServerState& s, SoupServerMessage* msg, std::initializer_list<const char*> types,
                    nlohmann::json* out) {
  SoupMessageHeaders* headers = soup_server_message_get_request_headers(msg);
  const char* type = soup_message_headers_get_content_type(headers, nullptr);
  bool accepted = false;
  for (const char* t : types) accepted = accepted || (type && g_ascii_strcasecmp(type, t) == 0);
  if (!accepted) {
    std::string list;
    for (const char* t : types) list += (list.empty() ? "" : " or ") + std::string(t);
    reply_problem(msg, s.metrics, SOUP_STATUS_UNSUPPORTED_MEDIA_TYPE, "the body must be " + list);
    return false;
  }
  SoupMessageBody* body = soup_server_message_get_request_body(msg);
  if (body->length > static_cast<goffset>(s.config.max_body_bytes)) {
    reply_problem(msg, s.metrics, SOUP_STATUS_REQUEST_ENTITY_TOO_LARGE,
                  "the body is larger than " + std::to_string(s.config.max_body_bytes) + " bytes");
    return false;
  }
  *out = nlohmann::json::parse(body->data, body->data + body->length, nullptr, false);
  if (out->is_discarded() || !out->is_object()) {
    reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST, "the body must be a JSON object");
    return false;
  }
  return true;
}

void create_session(ServerState& s, SoupServerMessage* msg) {
  nlohmann::json body;
  if (!read_json_body(s, msg, {"application/json"}, &body)) return;
  for (const auto& [key, value] : body.items())
    if (key != "scene" && key != "codec")
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, key + ": unknown key", key);
  if (!body.contains("scene") || !body["scene"].is_string())
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, "scene: must be a scene id (string)",
                         "scene");
  const std::string scene_id = body["scene"];
  auto entry = s.gallery->entries.find(scene_id);
  if (entry == s.gallery->entries.end())
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, "scene: no such scene", "scene");
  std::string codec = s.config.codec;
  if (body.contains("codec")) {
    if (!body["codec"].is_string() || (body["codec"] != "vp8" && body["codec"] != "h264"))
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, "codec: must be \"vp8\" or \"h264\"",
                           "codec");
    codec = body["codec"];
  }
  if (static_cast<int>(s.sessions.size()) >= s.config.max_sessions) {
    ++s.metrics.sessions_rejected;
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Retry-After", "10");
    return reply_problem(msg, s.metrics, SOUP_STATUS_SERVICE_UNAVAILABLE,
                         "the server is full (" + std::to_string(s.config.max_sessions) + " sessions)");
  }
  const std::string id = random_hex();
  ServerState* state = &s;
  SessionOptions options{codec, &s.config, s.data_dir, &s.metrics,
                         [state](const std::string& sid, const std::string& why) { state->end_session(sid, why); }};
  std::shared_ptr<Session> session;
  try {
    session = Session::start(id, entry->second, options);
  } catch (const std::exception& e) {
    log(Level::error, std::string("cannot start a session: ") + e.what());
    return reply_problem(msg, s.metrics, SOUP_STATUS_INTERNAL_SERVER_ERROR, "the stream could not be started");
  }
  s.sessions[id] = session;
  ++s.metrics.sessions_created;
  log(Level::info, "session " + id + " started: scene " + scene_id + ", " + codec);
  const std::string signal = "/api/v1/sessions/" + id + "/signal?token=" + session->token();
  soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Location",
                               ("/api/v1/sessions/" + id).c_str());
  reply_json(msg, SOUP_STATUS_CREATED,
             {{"id", id}, {"token", session->token()}, {"codec", codec}, {"signal_url", signal},
              {"params", public_params(*session)}});
}

void patch_params(ServerState& s, SoupServerMessage* msg, Session& session) {
  nlohmann::json patch;
  if (!read_json_body(s, msg, {"application/merge-patch+json", "application/json"}, &patch)) return;
  for (const auto& fixed : kFixedKeys) {
    const bool hit = fixed[1] ? patch.contains(fixed[0]) && patch[fixed[0]].is_object() &&
                                    patch[fixed[0]].contains(fixed[1])
                              : patch.contains(fixed[0]);
    if (hit) {
      const std::string key = fixed[1] ? std::string(fixed[0]) + "." + fixed[1] : fixed[0];
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, key + ": cannot be changed in a session",
                           key);
    }
  }
  try {
    session.params().apply_patch(patch);
  } catch (const SceneError& e) {
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, e.what(), e.key());
  }
  ++s.metrics.parameter_updates;
  reply_json(msg, SOUP_STATUS_OK, public_params(session));
}

void session_route(ServerState& s, SoupServerMessage* msg, const Route& route) {
  auto it = s.sessions.find(route.session);
  if (it == s.sessions.end()) return reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such session");
  Session& session = *it->second;
  const std::string token = bearer_token(msg);
  if (token.empty() || !same_secret(token, session.token())) {
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "WWW-Authenticate", "Bearer");
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNAUTHORIZED, "a valid bearer token for this session is needed");
  }
  const std::string method = method_of(msg);
  if (route.rest.empty() && method == "DELETE") {
    s.end_session(route.session, "deleted by its viewer");
    soup_server_message_set_status(msg, SOUP_STATUS_NO_CONTENT, nullptr);
    return;
  }
  if (route.rest == "/params" && method == "GET")
    return reply_json(msg, SOUP_STATUS_OK, public_params(session));
  if (route.rest == "/params" && method == "PATCH") return patch_params(s, msg, session);
  reply_problem(msg, s.metrics, SOUP_STATUS_METHOD_NOT_ALLOWED, method + " is not allowed here");
}

}  // namespace

void handle_http(SoupServer*, SoupServerMessage* msg, const char* raw_path, GHashTable*, gpointer data) {
  auto& s = *static_cast<ServerState*>(data);
  const std::string path = raw_path;
  const std::string method = method_of(msg);
  static const std::regex session_path("^/api/v1/sessions/([0-9a-f]{32})(/params)?$");
  static const std::regex thumbnail_path("^/api/v1/scenes/([a-z0-9_-]{1,64})/thumbnail\\.png$");
  std::smatch m;
  const bool read = method == "GET" || method == "HEAD";
  if (path == "/api/v1/health" && read) return health(s, msg);
  if (path == "/api/v1/scenes" && read) return scenes(s, msg);
  if (std::regex_match(path, m, thumbnail_path) && read) return thumbnail(s, msg, m[1]);
  if (path == "/api/v1/sessions" && method == "POST") return create_session(s, msg);
  if (std::regex_match(path, m, session_path)) return session_route(s, msg, {m[1], m[2]});
  static const std::regex signal_path("^/api/v1/sessions/([0-9a-f]{32})/signal$");
  if (std::regex_match(path, m, signal_path) && method == "GET") {
    // libsoup asks this handler first: leaving the status unset lets the
    // WebSocket handshake go ahead; any answer refuses it.
    auto it = s.sessions.find(m[1]);
    if (it == s.sessions.end()) return reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such session");
    if (!same_secret(query_token(msg), it->second->token()))
      return reply_problem(msg, s.metrics, SOUP_STATUS_UNAUTHORIZED, "the token does not match the session");
    const char* upgrade =
        soup_message_headers_get_one(soup_server_message_get_request_headers(msg), "Upgrade");
    if (!upgrade || g_ascii_strcasecmp(upgrade, "websocket") != 0)
      return reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST, "this is a WebSocket endpoint");
    return;
  }
  if (path == "/metrics" && read) {
    const std::string text = s.metrics.render(s.sessions.size());
    return reply_bytes(msg, SOUP_STATUS_OK, "text/plain; version=0.0.4", text.data(), text.size());
  }
  if (path.rfind("/api/", 0) == 0) {
    const bool known = path == "/api/v1/health" || path == "/api/v1/scenes" || path == "/api/v1/sessions" ||
                       std::regex_match(path, thumbnail_path);
    return reply_problem(msg, s.metrics, known ? SOUP_STATUS_METHOD_NOT_ALLOWED : SOUP_STATUS_NOT_FOUND,
                         known ? method + " is not allowed here" : "no such endpoint");
  }
  if (!read) return reply_problem(msg, s.metrics, SOUP_STATUS_METHOD_NOT_ALLOWED, method + " is not allowed here");
  serve_static(web_folder(s.config, s.data_dir), path, msg, s.metrics);
}

void handle_signal_socket(SoupServer*, SoupServerMessage* msg, const char* raw_path, SoupWebsocketConnection* socket,
                          gpointer data) {
  auto& s = *static_cast<ServerState*>(data);
  static const std::regex signal_path("^/api/v1/sessions/([0-9a-f]{32})/signal$");
  std::smatch m;
  const std::string path = raw_path;
  const std::string token = query_token(msg);
  auto it = std::regex_match(path, m, signal_path) ? s.sessions.find(m[1]) : s.sessions.end();
  if (it == s.sessions.end() || !same_secret(token, it->second->token())) {
    ++s.metrics.http_errors;
    soup_websocket_connection_close(socket, SOUP_WEBSOCKET_CLOSE_POLICY_VIOLATION, "unknown session or wrong token");
    return;
  }
  it->second->attach(socket);
}

void handle_early(SoupServer*, SoupServerMessage* msg, const char*, GHashTable*, gpointer data) {
  auto& s = *static_cast<ServerState*>(data);
  SoupMessageHeaders* headers = soup_server_message_get_request_headers(msg);
  const goffset length = soup_message_headers_get_content_length(headers);
  if (length > static_cast<goffset>(s.config.max_body_bytes))
    reply_problem(msg, s.metrics, SOUP_STATUS_REQUEST_ENTITY_TOO_LARGE,
                  "the body is larger than " + std::to_string(s.config.max_body_bytes) + " bytes");
}

}  // namespace caustic::server
