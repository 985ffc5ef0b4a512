// SPDX-License-Identifier: LGPL-2.1-or-later
// The REST API of docs/api.md (openapi.yaml).
#include "caustic/receivers.hpp"
#include "caustic/json_text.hpp"
#include "caustic/scene_warnings.hpp"
#include "caustic/screen_follow.hpp"
#include "caustic/spectral.hpp"
#include "address_group.hpp"
#include "http_util.hpp"
#include "log.hpp"
#include "server_state.hpp"
#include "static_files.hpp"

#include <algorithm>
#include <regex>

namespace caustic::server {
namespace {

// Signalling sockets for a session: a burst of this many (the first, then
// a page reloaded twice or a second tab taking over), then one every 2 s.
constexpr double kReconnectBurst = 3, kReconnectsPerS = 0.5;
// Patches that set a session's receivers: a burst of this many, then two a second.
constexpr double kReceiverPatchBurst = 8, kReceiverPatchesPerS = 2;

// Keys a session's viewer may not patch: the mesh, its flat face and the
// gallery text belong to the scene (moving the flat face and watching which
// offsets are refused would map the hidden surface; the shape says what the
// mesh is), the size to the negotiated stream, the water's grid and size to
// the surface its solver moves (and turning water on or off changes both).
const char* const kFixedKeys[][2] = {{"mesh", nullptr},           {"name", nullptr},
                                     {"description", nullptr},    {"render", "width"},
                                     {"render", "height"},        {"object", "flat_face_normal"},
                                     {"object", "flat_face_offset"}, {"object", "shape"},
                                     {"water", "grid"},           {"water", "size"}};

struct Route {
  std::string session;  // id, when the path names one
  std::string rest;     // what follows /api/v1/sessions/{id}
};

std::string method_of(SoupServerMessage* msg) { return soup_server_message_get_method(msg); }

// Browsers cannot set headers on a WebSocket: its token travels in the query.
std::string query_token(SoupServerMessage* msg) {
  std::string token;
  if (const char* query = request_query(msg)) {
    GHashTable* form = soup_form_decode(query);
    if (const char* t = static_cast<const char*>(g_hash_table_lookup(form, "token"))) token = t;
    g_hash_table_unref(form);
  }
  return token;
}

// 503 while draining: a proxy's health check then stops sending new
// sessions here, while the routes of running sessions go on regardless.
void health(ServerState& s, SoupServerMessage* msg) {
  nlohmann::json body = {{"status", s.draining ? "draining" : "ok"}, {"version", CAUSTICD_VERSION},
                         {"sessions", s.sessions.size()}, {"max_sessions", s.config.max_sessions},
                         {"free_sessions", free_sessions(s)}};
  if (s.config.instance_index > 0) body["instance"] = s.config.instance_index;
  reply_json(msg, s.draining ? SOUP_STATUS_SERVICE_UNAVAILABLE : SOUP_STATUS_OK, body);
}

void scenes(ServerState& s, SoupServerMessage* msg) {
  nlohmann::json list = nlohmann::json::array();
  // Designed objects first, then the optics classics; by id within each.
  for (const bool designed : {true, false})
    for (const auto& [id, entry] : s.gallery->entries)
      if (entry->designed == designed) list.push_back(describe(*entry));
  // The catalogue glasses a scene's object.glass may name (the viewer's panel offers them).
  nlohmann::json glasses = nlohmann::json::array();
  for (const auto& m : optics::materials()) glasses.push_back(m.name);
  reply_json(msg, SOUP_STATUS_OK, {{"scenes", list}, {"glasses", glasses}});
}

// A visitor's design answers from what its job keeps: its scene need not be
// in memory for this.
void scene(ServerState& s, SoupServerMessage* msg, const std::string& id) {
  if (const auto it = s.gallery->entries.find(id); it != s.gallery->entries.end()) {
    nlohmann::json body = describe(*it->second);
    if (!it->second->shapes.is_null()) body["receiver_meshes"] = it->second->shapes;  // here only: not in the list
    return reply_json(msg, SOUP_STATUS_OK, body);
  }
  if (const auto info = s.designs ? s.designs->scene_info(id) : std::nullopt) return reply_json(msg, SOUP_STATUS_OK, *info);
  reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such scene");
}

void thumbnail(ServerState& s, SoupServerMessage* msg, const std::string& id) {
  if (const auto it = s.gallery->entries.find(id); it != s.gallery->entries.end()) {
    const auto& png = it->second->thumbnail_png;
    return reply_bytes(msg, SOUP_STATUS_OK, "image/png", png.data(), png.size());
  }
  const auto png = s.designs ? s.designs->thumbnail(id) : std::vector<unsigned char>();
  if (png.empty()) return reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such scene");
  reply_bytes(msg, SOUP_STATUS_OK, "image/png", png.data(), png.size());
}

// The parameters' version as a strong entity tag: a client that read
// version N patches with If-Match: "N", and a patch that came between is
// not overwritten unseen (RFC 9110 13.1.1).
std::string params_etag(Session& session) {
  return "\"" + std::to_string(session.params().snapshot().version) + "\"";
}

void reply_params(SoupServerMessage* msg, guint status, Session& session, nlohmann::json body) {
  soup_message_headers_replace(soup_server_message_get_response_headers(msg), "ETag", params_etag(session).c_str());
  reply_json(msg, status, body);
}

void patch_params(ServerState& s, SoupServerMessage* msg, Session& session) {
  nlohmann::json patch;
  if (!read_json_body(s, msg, {"application/merge-patch+json", "application/json"}, &patch)) return;
  const bool conditional = soup_message_headers_get_one(soup_server_message_get_request_headers(msg), "If-Match");
  if (const std::string etag = params_etag(session); conditional && !lists_tag(msg, "If-Match", etag, false)) {
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "ETag", etag.c_str());
    return reply_problem(msg, s.metrics, SOUP_STATUS_PRECONDITION_FAILED,
                         "If-Match: the parameters are at version " + etag + " now; read them and patch again");
  }
  // Receivers set anew may each build triangles and a search tree (a lathe,
  // a shape: tens of milliseconds on the main loop): a few at once, then
  // two a second for each session.
  if (patch.is_object() && patch.contains("receivers") &&
      !s.within(s.receiver_rate, msg, session.id(), kReceiverPatchesPerS, kReceiverPatchBurst,
                "receivers: this session sets its receivers too often", "receivers"))
    return;
  // Compared on the result, not looked up in the patch: a null higher up
  // ("object": null) resets the keys below it too.
  const nlohmann::json before = scene_to_json(session.params().snapshot().scene);
  nlohmann::json after;
  try {
    after = scene_to_json(apply_merge_patch(session.params().snapshot().scene, patch, &session.params().origin()));
  } catch (const SceneError& e) {
    return reply_problem(msg, s.metrics, SOUP_STATUS_UNPROCESSABLE_ENTITY, e.what(), e.key());
  }
  for (const auto& fixed : kFixedKeys) {
    const nlohmann::json::json_pointer at(std::string("/") + fixed[0] + (fixed[1] ? std::string("/") + fixed[1] : ""));
    const auto value = [&](const nlohmann::json& j) { return j.contains(at) ? j.at(at) : nlohmann::json(); };
    if (value(before) != value(after)) {
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
  nlohmann::json overridden = nlohmann::json::array();
  const Scene now = session.params().snapshot().scene;
  for (const auto& [key, detail] : scene_overrides(patch, now)) overridden.push_back({{"key", key}, {"detail", detail}});
  reply_params(msg, SOUP_STATUS_OK, session, public_params(session, std::move(overridden)));
}

// One answer for an unknown session and for a wrong token: which session
// ids exist is nobody's business but their holders'.
void refuse_session(ServerState& s, SoupServerMessage* msg) {
  soup_message_headers_replace(soup_server_message_get_response_headers(msg), "WWW-Authenticate", "Bearer");
  reply_problem(msg, s.metrics, SOUP_STATUS_UNAUTHORIZED, "no session with this id and token");
}

void session_route(ServerState& s, SoupServerMessage* msg, const Route& route) {
  auto it = s.sessions.find(route.session);
  const std::string token = bearer_token(msg);
  if (it == s.sessions.end() || token.empty() || !same_secret(token, it->second->token())) return refuse_session(s, msg);
  Session& session = *it->second;
  const std::string method = method_of(msg);
  if (route.rest.empty()) {
    if (method != "DELETE") return not_allowed(s, msg, "DELETE");
    s.end_session(route.session, "deleted by its viewer");
    soup_server_message_set_status(msg, SOUP_STATUS_NO_CONTENT, nullptr);
    return;
  }
  // A broadcast's holder is there; a one-viewer session's liveness is its
  // viewer's (RTCP, signalling), which a REST client polling must not fake.
  if (session.broadcast()) session.alive_now();
  if (route.rest == "/viewers")
    return method == "POST" ? broadcast_viewers(s, msg, session) : not_allowed(s, msg, "POST");
  if (route.rest == "/drops") return method == "POST" ? post_drop(s, msg, session) : not_allowed(s, msg, "POST");
  if (route.rest != "/params") {
    if (method != "GET" && method != "HEAD") return not_allowed(s, msg, "GET, HEAD");
    return session_frame(s, msg, session, route.rest == "/frame.exr");
  }
  if (method == "GET" || method == "HEAD") {
    reply_params(msg, SOUP_STATUS_OK, session, public_params(session));
    // A client polling with the tag it holds hears only of a change; the
    // 304 keeps the 200's length (RFC 9110 8.6) and writes no body.
    if (lists_tag(msg, "If-None-Match", params_etag(session), true)) {
      soup_server_message_set_status(msg, SOUP_STATUS_NOT_MODIFIED, nullptr);
      soup_message_headers_remove(soup_server_message_get_response_headers(msg), "Content-Type");
    }
    return;
  }
  if (method == "PATCH") return patch_params(s, msg, session);
  not_allowed(s, msg, "GET, HEAD, PATCH");
}

// What a mutating request costs: a token from its address's bucket.
bool within_rate(ServerState& s, SoupServerMessage* msg) {
  return s.within(s.rate_limiter, msg, address_group(client_address(msg, s.config.trusted_proxies)),
                  s.config.rate_limit_per_s, s.config.rate_limit_burst, "too many requests from your address");
}

void route_http(ServerState& s, SoupServerMessage* msg, const std::string& path) {
  const std::string method = method_of(msg);
  static const std::regex session_path(
      "^/api/v1/sessions/([0-9a-f]{32})(/params|/frame\\.png|/frame\\.exr|/viewers|/drops)?$");
  static const std::regex scene_path("^/api/v1/scenes/([a-z0-9_-]{1,64})$");
  static const std::regex thumbnail_path("^/api/v1/scenes/([a-z0-9_-]{1,64})/thumbnail\\.png$");
  static const std::regex signal_path("^/api/v1/sessions/([0-9a-f]{32})/signal$");
  std::smatch m;
  // A request that asked to become a WebSocket may have been let go of its
  // connection's timeouts (request_head.cpp): unless it becomes one, on
  // the signalling path below, its connection closes after the answer.
  if (soup_message_headers_get_one(soup_server_message_get_request_headers(msg), "Upgrade") &&
      !std::regex_match(path, signal_path))
    soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Connection", "close");
  const bool read = method == "GET" || method == "HEAD";
  const bool mutating = method == "POST" || method == "PATCH" || method == "DELETE" || method == "PUT";
  if (mutating && !within_rate(s, msg)) return;
  if (path == "/api/v1/health") return read ? health(s, msg) : not_allowed(s, msg, "GET, HEAD");
  if (path == "/api/v1/scenes") return read ? scenes(s, msg) : not_allowed(s, msg, "GET, HEAD");
  if (std::regex_match(path, m, scene_path)) return read ? scene(s, msg, m[1]) : not_allowed(s, msg, "GET, HEAD");
  if (std::regex_match(path, m, thumbnail_path)) return read ? thumbnail(s, msg, m[1]) : not_allowed(s, msg, "GET, HEAD");
  if (path == "/api/v1/sessions") return method == "POST" ? create_session(s, msg) : not_allowed(s, msg, "POST");
  if (std::regex_match(path, m, session_path)) return session_route(s, msg, {m[1], m[2]});
  if (route_designs(s, msg, path)) return;
  if (std::regex_match(path, m, signal_path)) {
    if (method != "GET") return not_allowed(s, msg, "GET");
    // libsoup asks this handler first: leaving the status unset lets the
    // WebSocket handshake go ahead; any answer refuses it, and closes the
    // connection, which the listener let go of its timeouts for the socket
    // it was to become.
    const auto closing = [&] {
      soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Connection", "close");
    };
    auto it = s.sessions.find(m[1]);
    if (it == s.sessions.end() || !same_secret(query_token(msg), it->second->token()))
      return closing(), refuse_session(s, msg);
    const char* upgrade = soup_message_headers_get_one(soup_server_message_get_request_headers(msg), "Upgrade");
    if (!upgrade || g_ascii_strcasecmp(upgrade, "websocket") != 0)
      return closing(), reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST, "this is a WebSocket endpoint");
    // The library would refuse a broken handshake with a bare 400; say why.
    GError* error = nullptr;
    if (!soup_websocket_server_check_handshake(msg, nullptr, nullptr, nullptr, &error)) {
      const std::string why = error ? error->message : "invalid handshake";
      if (error) g_error_free(error);
      return closing(), reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST, "not a valid WebSocket handshake: " + why);
    }
    // Only a connection the accept path let go of as a WebSocket has its
    // frames followed (message size, frame rate): a handshake that came with
    // a body, or with "/signal" escaped in its path, would have become a
    // socket without those limits.
    if (s.listener && !s.listener->guards_websocket(msg))
      return closing(), reply_problem(msg, s.metrics, SOUP_STATUS_BAD_REQUEST,
                                      "a WebSocket handshake is a GET without a body, its path ending in /signal as "
                                      "written, without escapes");
    // A socket that replaces the viewer's rebuilds the whole stream (a
    // pipeline, its encoder and renderer): a loop of them would spend the
    // machine on rebuilds. Every handshake counts, the first too (sockets
    // made side by side all attach after their handshakes): a session
    // takes a few at once, then one every 2 s.
    if (!s.within(s.reconnect_rate, msg, it->first, kReconnectsPerS, kReconnectBurst,
                  "this session's stream was rebuilt for new connections too often"))
      return closing();
    // Going ahead: the 101's Connection field is the upgrade's alone, not
    // beside the "close" that every plain answer carries (on_request_started).
    soup_message_headers_remove(soup_server_message_get_response_headers(msg), "Connection");
    return;
  }
  if (path == "/metrics") {
    if (!read) return not_allowed(s, msg, "GET, HEAD");
    const std::string text =
        s.metrics.render(s.sessions.size(), s.listener ? static_cast<std::size_t>(s.listener->open_connections()) : 0);
    return reply_bytes(msg, SOUP_STATUS_OK, "text/plain; version=0.0.4", text.data(), text.size());
  }
  if (path.rfind("/api/", 0) == 0) return reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such endpoint");
  if (!read) return not_allowed(s, msg, "GET, HEAD");
  serve_static(web_folder(s.config, s.data_dir), path, msg, s.metrics, s.config.janus_ws_url);
}

}  // namespace

// `extra`: warnings about what the request itself wrote (keys that fidelity
// "auto" overrides); the light's are judged on the public proxy every time.
nlohmann::json public_params(Session& session, nlohmann::json extra) {
  const ParamStore::Snapshot snap = session.params().snapshot();
  nlohmann::json params = scene_to_json(snap.scene);
  params.erase("mesh");  // a protected mesh is not even named
  params.erase("receiver_meshes");  // file paths; the shapes' names are in the receivers, their geometry in the scene's
  nlohmann::json warnings = std::move(extra);
  for (const auto& w : light_warnings(snap.scene, session.entry().levels->place(snap.scene.object)))
    warnings.push_back({{"key", w.key}, {"detail", w.detail}});
  // Where each surface (the screen, then the receivers) lies in the picture.
  nlohmann::json atlas = nlohmann::json::array();
  for (const auto& t : atlas_layout(snap.scene.render.width, snap.scene.render.height, 1 + snap.scene.receivers.size()))
    atlas.push_back({{"x", t.x}, {"y", t.y}, {"width", t.width}, {"height", t.height}});
  return {{"version", snap.version},
          {"params", params},
          {"atlas", atlas},
          {"fidelity", fidelity_of(session.entry(), snap.scene)},
          {"warnings", warnings}};
}

void not_allowed(ServerState& s, SoupServerMessage* msg, const char* allow) {
  soup_message_headers_replace(soup_server_message_get_response_headers(msg), "Allow", allow);
  reply_problem(msg, s.metrics, SOUP_STATUS_METHOD_NOT_ALLOWED, std::string("this resource allows ") + allow);
}

void handle_http(SoupServer*, SoupServerMessage* msg, const char*, GHashTable*, gpointer data) {
  auto& s = *static_cast<ServerState*>(data);
  // Nothing may leave a C callback as an exception: it would end the
  // process. A failure here is the server's fault, and says so.
  try {
    std::string path = request_path(msg);  // "%2F" names no route, and static files decode once
    if (strip_instance_prefix(s.config, path) == PathOwner::other_instance)
      return reply_problem(msg, s.metrics, 421, "this is not the instance that path names");
    route_http(s, msg, path);
  } catch (const std::exception& e) {
    log(Level::error, std::string("request failed: ") + e.what());
    reply_problem(msg, s.metrics, SOUP_STATUS_INTERNAL_SERVER_ERROR, "the request failed inside the server");
  } catch (...) {
    log(Level::error, "request failed with an unknown exception");
    reply_problem(msg, s.metrics, SOUP_STATUS_INTERNAL_SERVER_ERROR, "the request failed inside the server");
  }
}

void handle_signal_socket(SoupServer*, SoupServerMessage* msg, const char*, SoupWebsocketConnection* socket,
                          gpointer data) {
  auto& s = *static_cast<ServerState*>(data);
  try {
    static const std::regex signal_path("^/api/v1/sessions/([0-9a-f]{32})/signal$");
    std::smatch m;
    std::string path = request_path(msg);  // as handle_http routes it
    strip_instance_prefix(s.config, path);  // another's prefix then matches no session
    const std::string token = query_token(msg);
    auto it = std::regex_match(path, m, signal_path) ? s.sessions.find(m[1]) : s.sessions.end();
    if (it == s.sessions.end() || !same_secret(token, it->second->token())) {
      ++s.metrics.http_errors;
      soup_websocket_connection_close(socket, SOUP_WEBSOCKET_CLOSE_POLICY_VIOLATION, "unknown session or wrong token");
      return;
    }
    if (it->second->broadcast()) {
      soup_websocket_connection_close(socket, SOUP_WEBSOCKET_CLOSE_POLICY_VIOLATION,
                                      "a broadcast is watched through its viewer links");
      return;
    }
    // A viewer coming back rebuilds the session's pipeline: when that
    // fails the session has no stream left, and ends rather than hold its
    // slot until the idle reclaim.
    const std::shared_ptr<Session> session = it->second;
    const std::string id = m[1];
    try {
      session->attach(socket);
    } catch (const std::exception& e) {
      log(Level::error, std::string("the stream could not be restarted: ") + e.what(), session->log_context());
      soup_websocket_connection_close(socket, SOUP_WEBSOCKET_CLOSE_SERVER_ERROR, "server error");
      s.end_session(id, "the stream could not be restarted");
    }
  } catch (const std::exception& e) {
    log(Level::error, std::string("signalling socket failed: ") + e.what());
    soup_websocket_connection_close(socket, SOUP_WEBSOCKET_CLOSE_SERVER_ERROR, "server error");
  }
}

void on_request_started(SoupServer*, SoupServerMessage* msg, gpointer data) {
  // Every plain answer closes its connection: libsoup 3.2 leaks the socket
  // of a keep-alive connection that the client closes (fixed in 3.3), and
  // one request per connection is what the accept path's limits count.
  SoupMessageHeaders* headers = soup_server_message_get_response_headers(msg);
  soup_message_headers_replace(headers, "Connection", "close");
  soup_message_headers_replace(headers, "X-Content-Type-Options", "nosniff");
  soup_message_headers_replace(headers, "Referrer-Policy", "no-referrer");
  soup_message_headers_replace(headers, "X-Frame-Options", "DENY");
  soup_message_headers_replace(headers, "Accept-Ranges", "none");  // on_request_read
  const auto& state = *static_cast<ServerState*>(data);
  const auto& config = state.config;
  soup_message_headers_replace(headers, "Content-Security-Policy", state.api_policy.c_str());
  // Which instance answered, for an operator reading a proxy's traffic.
  if (const int n = config.instance_index; n > 0)
    soup_message_headers_replace(headers, "X-Causticd-Instance", std::to_string(n).c_str());
}

void on_request_read(SoupServer*, SoupServerMessage* msg, gpointer) {
  // libsoup 3.2 serves the ranges of any 200 itself: every range of a
  // multi-range request copied into one body in memory (a thousand copies
  // of a megabyte file for one 16 KiB head), and a suffix longer than the
  // file as a broken 206. A server may ignore Range (RFC 9110 14.2); the
  // files here are small, and an answer is whole.
  SoupMessageHeaders* headers = soup_server_message_get_request_headers(msg);
  soup_message_headers_remove(headers, "Range");
  soup_message_headers_remove(headers, "If-Range");
}

}  // namespace caustic::server
