// SPDX-License-Identifier: LGPL-2.1-or-later
#include "broadcast.hpp"

#include "address_group.hpp"
#include "http_util.hpp"
#include "janus_admin.hpp"
#include "janus_requests.hpp"
#include "log.hpp"
#include "mountpoint_ledger.hpp"
#include "server_state.hpp"

#include <glib.h>

#include <chrono>
#include <set>

namespace caustic::server {
namespace {

// Strays beyond the server's sessions and this many more are forgotten
// (each costs a request every check, and one at stop): a Janus that never
// answers takes no more of the server.
constexpr std::size_t max_strays = 64;
constexpr int stray_checks = 30;  // a minute of checks 2 s apart
// Past that minute, a Janus that does not answer (frozen, or swapped out)
// is asked every this many checks: it may wake with the mountpoint, which
// stays listed meanwhile, so that even a kill leaves it to the next start.
constexpr int slow_checks = 5;

std::size_t stray_limit(const ServerState& s) { return max_strays + static_cast<std::size_t>(s.config.max_sessions); }

StrayMountpoint& keep_stray(ServerState& s, const Mountpoint& m, StrayMountpoint::Origin origin) {
  if (s.strays.size() >= stray_limit(s) && !s.strays.count(m.id)) {
    log(Level::warning, "mountpoint " + std::to_string(s.strays.begin()->first) +
                            " is no longer asked after: too many destroys went unanswered");
    s.strays.erase(s.strays.begin());
  }
  return s.strays[m.id] = StrayMountpoint{m, origin};
}

// Asks Janus to destroy the stray; it goes from the list once Janus has,
// or says it has none (twice, unless it surely made it).
void ask_destroy(ServerState& s, StrayMountpoint& stray) {
  static std::uint64_t requests = 0;
  const std::uint64_t request = stray.asking = ++requests;
  ServerState* state = &s;
  const std::uint64_t id = stray.m.id;
  s.janus->plugin_request(destroy_request(stray.m), [state, id, request](const JanusAdmin::Answer& a) {
    const auto it = state->strays.find(id);
    if (it == state->strays.end() || it->second.asking != request) return;
    StrayMountpoint& stray = it->second;
    using Origin = StrayMountpoint::Origin;
    stray.asking = 0;
    ++stray.asked;
    const std::string name = "mountpoint " + std::to_string(id);
    if (a.error.empty()) {
      if (stray.origin == Origin::unanswered)
        log(Level::notice, name + ", made by Janus after the server gave up on it, is destroyed");
      else if (stray.origin == Origin::leftover)
        log(Level::notice, name + ", left in Janus by an earlier run of the server, is destroyed");
    } else if (a.error_code == 455 && (stray.origin == Origin::ended || ++stray.absent >= 2)) {
      // Janus answers and has none: gone, or never made.
    } else {
      if (stray.origin == Origin::ended && stray.asked == 1) log(Level::warning, name + " not destroyed: " + a.error);
      if (stray.asked == stray_checks)
        log(Level::warning, name + " not destroyed after a minute of asking (" + a.error + "); asked every " +
                                std::to_string(2 * slow_checks) + " s until Janus answers");
      return;  // asked again at a later check
    }
    state->strays.erase(it);
    record_mountpoints(*state);
  });
}

// Listed until Janus answers its destroy: a server killed meanwhile
// destroys it at its next start.
void destroy(ServerState& s, const Mountpoint& m) {
  if (!s.janus) return;
  ask_destroy(s, keep_stray(s, m, StrayMountpoint::Origin::ended));
  record_mountpoints(s);
}

void check_strays(ServerState& s) {
  // Ids first: an answer given at once (a bad URL) may end a stray.
  std::vector<std::uint64_t> ids;
  for (auto& [mid, stray] : s.strays)
    if (!stray.asking && (stray.asked < stray_checks || ++stray.checks % slow_checks == 0)) ids.push_back(mid);
  for (const std::uint64_t id : ids)
    if (const auto it = s.strays.find(id); it != s.strays.end()) ask_destroy(s, it->second);
}

// A paused request, answered once Janus has. Holds the message; a client
// that went away meanwhile is noticed.
struct Pending {
  SoupServerMessage* msg;
  bool gone = false;
  gulong handler = 0;
  explicit Pending(SoupServerMessage* m) : msg(SOUP_SERVER_MESSAGE(g_object_ref(m))) {
    handler = g_signal_connect(msg, "disconnected", G_CALLBACK(+[](SoupServerMessage*, gpointer self) {
                                 static_cast<Pending*>(self)->gone = true;
                               }),
                               this);
    // A status now: libsoup would otherwise take the unanswered request on
    // this path for a failed WebSocket handshake. The answer replaces it.
    soup_server_message_set_status(msg, SOUP_STATUS_INTERNAL_SERVER_ERROR, nullptr);
    soup_server_message_pause(msg);
  }
  // One owner of the reference: a copy would release it twice.
  Pending(const Pending&) = delete;
  Pending& operator=(const Pending&) = delete;
  ~Pending() {
    g_signal_handler_disconnect(msg, handler);
    if (!gone) soup_server_message_unpause(msg);
    g_object_unref(msg);
  }
};

// Janus gives a mountpoint's ports from its range in turn, RTCP the port
// after RTP only when that one is free: once its range has wrapped, a port
// held by a live mountpoint can split the pair. The stream's RTCP goes to the
// port after its RTP, so such a pair is destroyed and asked for again; Janus
// has moved on by then, and the next pair is most likely whole.
constexpr int kCreateTries = 3;

// One create request for session `id`'s mountpoint, `tries` of them left.
void ask_create(ServerState& s, std::shared_ptr<Pending> pending, std::shared_ptr<const GalleryEntry> entry,
                const std::string& codec, const std::string& address, const std::string& id, int tries) {
  Mountpoint m;
  m.id = std::stoull(random_hex().substr(0, 12), nullptr, 16) | 1;  // Janus's ids: positive, not 0
  m.secret = random_hex();
  m.pin = random_hex().substr(0, 16);
  ServerState* state = &s;
  const std::string group = address_group(address);
  ++s.starting[group];  // until the answer (the callback runs once, whatever Janus does)
  s.creating[m.id] = m;  // a stop before the answer destroys it too
  record_mountpoints(s);  // and so does the next start, after a kill
  s.janus->plugin_request(create_request(m, id, codec, s.config), [=](const JanusAdmin::Answer& a) mutable {
    ServerState& st = *state;
    st.creating.erase(m.id);
    // However it ends (running, a stray, destroyed, never made), listed so.
    struct Listed {
      ServerState& s;
      ~Listed() { record_mountpoints(s); }
    } listed{st};
    if (const auto it = st.starting.find(group); it != st.starting.end() && --it->second <= 0) st.starting.erase(it);
    SoupServerMessage* out = pending->msg;
    if (!a.error.empty()) {
      log(Level::error, "broadcast: Janus did not create the mountpoint: " + a.error, {id, entry->id, codec, address});
      if (a.unanswered) keep_stray(st, m, StrayMountpoint::Origin::unanswered);
      return reply_problem(out, st.metrics, SOUP_STATUS_BAD_GATEWAY, "the broadcast server did not take the stream");
    }
    if (!read_ports(a.response, m)) {
      destroy(st, m);
      if (tries > 1 && !st.draining && !pending->gone && st.listener->client_connected(out)) {
        log(Level::warning, "broadcast: Janus gave mountpoint " + std::to_string(m.id) +
                                " ports the stream cannot use (its RTCP must be on the port after RTP); asking again",
            {id, entry->id, codec, address});
        return ask_create(st, pending, entry, codec, address, id, tries - 1);
      }
      return reply_problem(out, st.metrics, SOUP_STATUS_BAD_GATEWAY, "the broadcast server gave unusable ports");
    }
    // While Janus answered, the client may have left, or the server begun
    // to stop or filled up: the mountpoint goes again, and each is said.
    if (pending->gone || !st.listener->client_connected(out)) {
      destroy(st, m);
      log(Level::info, "broadcast not started: its client went away while Janus answered", {id, entry->id, codec, address});
      return;
    }
    if (st.draining || static_cast<int>(st.sessions.size()) >= st.config.max_sessions) {
      destroy(st, m);
      soup_message_headers_replace(soup_server_message_get_response_headers(out), "Retry-After", "10");
      return reply_problem(out, st.metrics, SOUP_STATUS_SERVICE_UNAVAILABLE,
                           st.draining ? "this instance is stopping and takes no new sessions"
                                       : "the server is full (" + std::to_string(st.config.max_sessions) + " sessions)");
    }
    // Requests made side by side were each counted before any was answered.
    if (const int held = st.sessions_held_by(address); held >= st.config.max_sessions_per_address) {
      destroy(st, m);
      ++st.metrics.sessions_rejected;
      soup_message_headers_replace(soup_server_message_get_response_headers(out), "Retry-After", "10");
      return reply_problem(out, st.metrics, 429,
                           "your address holds " + std::to_string(held) + " sessions already (the limit); end one first");
    }
    SessionOptions options{codec, address, &st.config, st.data_dir, &st.metrics,
                           [state](const std::string& sid, const std::string& why) { state->end_session(sid, why); },
                           RtpTarget{st.config.janus_rtp_address, m.video_port, m.data_port}};
    std::shared_ptr<Session> session;
    try {
      session = Session::start(id, entry, options);
    } catch (const std::exception& e) {
      destroy(st, m);
      log(Level::error, std::string("cannot start a broadcast: ") + e.what(), {id, entry->id, codec, address});
      return reply_problem(out, st.metrics, SOUP_STATUS_INTERNAL_SERVER_ERROR, "the stream could not be started");
    }
    st.sessions[id] = session;
    st.mountpoints[id] = m;
    ++st.metrics.sessions_created;
    log(Level::info, "broadcast " + id + " started: scene " + entry->id + ", " + codec + ", mountpoint " +
                         std::to_string(m.id),
        session->log_context());
    const std::string url = url_prefix(st.config) + "/api/v1/sessions/" + id;
    soup_message_headers_replace(soup_server_message_get_response_headers(out), "Location", url.c_str());
    reply_json(out, SOUP_STATUS_CREATED,
               {{"id", id}, {"token", session->token()}, {"codec", codec}, {"mode", "broadcast"}, {"url", url},
                {"viewers_url", url + "/viewers"}, {"params", public_params(*session)}});
  });
}

}  // namespace

void create_broadcast(ServerState& s, SoupServerMessage* msg, std::shared_ptr<const GalleryEntry> entry,
                      const std::string& codec, const std::string& address) {
  ask_create(s, std::make_shared<Pending>(msg), std::move(entry), codec, address, random_hex(), kCreateTries);
}

void broadcast_viewers(ServerState& s, SoupServerMessage* msg, Session& session) {
  const auto it = s.mountpoints.find(session.id());
  if (!session.broadcast() || it == s.mountpoints.end())
    return reply_problem(msg, s.metrics, SOUP_STATUS_CONFLICT, "this session is not a broadcast; its viewer is you");
  const Mountpoint& m = it->second;
  const std::int64_t expires = g_get_real_time() / G_USEC_PER_SEC + s.config.viewer_link_ttl_s;
  const std::string token = janus_token(s.config.janus_token_secret, expires);
  // In the fragment: a browser never sends it, so no log keeps the token.
  gchar* escaped = g_uri_escape_string(token.c_str(), nullptr, FALSE);
  gchar* janus = g_uri_escape_string(s.config.janus_ws_url.c_str(), nullptr, FALSE);
  const std::string watch = "/watch.html#scene=" + session.scene_id() + "&mountpoint=" + std::to_string(m.id) +
                            "&pin=" + m.pin + "&token=" + escaped + "&janus=" + janus;
  g_free(escaped);
  g_free(janus);
  session.alive_now();
  reply_json(msg, SOUP_STATUS_CREATED,
             {{"janus_url", s.config.janus_ws_url}, {"mountpoint", m.id},  {"pin", m.pin},
              {"token", token},                    {"expires", expires},   {"scene", session.scene_id()},
              {"instance", s.config.instance_index}, {"watch_url", watch}});
}

void end_broadcast(ServerState& s, const std::string& id) {
  const auto it = s.mountpoints.find(id);
  if (it == s.mountpoints.end()) return;
  destroy(s, it->second);
  s.mountpoints.erase(it);
}

void end_all_broadcasts(ServerState& s) {
  if (!s.janus) return;
  // Asked side by side: a Janus that does not answer holds the stop for one
  // timeout, not one per mountpoint.
  std::vector<std::string> sessions;  // "" for those of no session
  std::vector<nlohmann::json> requests;
  std::vector<Mountpoint> asked;
  std::set<std::uint64_t> ids;  // a re-create on its way is its session's too
  const auto add = [&](const std::string& session, const Mountpoint& m) {
    if (!ids.insert(m.id).second) return;
    sessions.push_back(session);
    requests.push_back(destroy_request(m));
    asked.push_back(m);
  };
  for (const auto& [id, m] : s.mountpoints) add(id, m);
  // Strays, and creates still waiting for their answer: sent after the
  // create, the destroy comes after it to a Janus that answers (one that is
  // frozen may take them in either order when it wakes).
  for (const auto& [mid, stray] : s.strays) add("", stray.m);
  for (const auto& [mid, m] : s.creating) add("", m);
  // Janus's "none" to these may come before it carries out their create.
  std::set<std::uint64_t> creating;
  for (const auto& [mid, m] : s.creating) creating.insert(mid);
  const auto answers = s.janus->plugin_requests_now(std::move(requests));
  s.mountpoints.clear();
  s.strays.clear();
  s.creating.clear();
  // Those Janus did not say are gone stay listed, for the next start.
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const auto& a = answers[i];
    const bool unsure = creating.count(asked[i].id) > 0;
    if (a.error.empty() || (a.error_code == 455 && !unsure)) continue;
    if (!sessions[i].empty() && a.error_code != 455) log(Level::warning, "broadcast " + sessions[i] + ": mountpoint not destroyed: " + a.error);
    s.strays[asked[i].id] = StrayMountpoint{asked[i], StrayMountpoint::Origin::leftover};
  }
  record_mountpoints(s);
  s.strays.clear();
  // Nothing more is asked of Janus, and an answer still on its way (a
  // create's, while the server stops) is dropped: it would start a session
  // in a server being taken down.
  s.janus.reset();
}

void destroy_leftover_mountpoints(ServerState& s) {
  if (!s.janus) return;
  const auto file = ledger_file(state_folder(s.config));
  std::string problem;
  // At most what a run lists: its sessions' mountpoints and its strays.
  const std::size_t most = static_cast<std::size_t>(s.config.max_sessions) + stray_limit(s);
  const MountpointLedger leftovers = read_ledger(file, most, &problem);
  if (!problem.empty())
    log(Level::warning, "broadcasts: " + file.string() + ": " + problem + (leftovers.empty() ? "; it is ignored" : ""));
  for (const auto& [id, secret] : leftovers) {
    Mountpoint m;
    m.id = id;
    m.secret = secret;
    s.strays[id] = StrayMountpoint{m, StrayMountpoint::Origin::leftover};
  }
  if (!leftovers.empty())
    log(Level::notice, "broadcasts: destroying " + std::to_string(leftovers.size()) + " mountpoints that " + file.string() +
                           " lists, left in Janus by an earlier run");
  record_mountpoints(s);  // a damaged ledger is replaced
}

void check_broadcasts(ServerState& s) {
  if (!s.janus) return;
  check_strays(s);
  ServerState* state = &s;
  for (auto& [sid, mountpoint] : s.mountpoints) {
    const auto now = std::chrono::steady_clock::now();
    if (mountpoint.recreating != std::chrono::steady_clock::time_point{} &&
        now - mountpoint.recreating < std::chrono::seconds(10))
      continue;
    const std::string id = sid;
    s.janus->plugin_request(
        {{"request", "info"}, {"id", mountpoint.id}, {"secret", mountpoint.secret}},
        [state, id](const JanusAdmin::Answer& a) {
          auto it = state->mountpoints.find(id);
          auto session = state->sessions.find(id);
          if (!a.error.empty() && a.error_code != 455)
            log(Level::debug, "broadcast " + id + ": mountpoint check: " + a.error);
          if (a.error_code != 455 || it == state->mountpoints.end() || session == state->sessions.end()) return;
          // Janus lost it (a restart): the same id, secret, pin and ports.
          // Listed as a create until answered: its session may end meanwhile.
          Mountpoint& m = it->second;
          m.recreating = std::chrono::steady_clock::now();
          state->creating[m.id] = m;
          log(Level::notice, "broadcast " + id + ": Janus lost mountpoint " + std::to_string(m.id) +
                                 "; creating it again", session->second->log_context());
          state->janus->plugin_request(
              create_request(m, id, session->second->codec(), state->config),
              [state, id, m](const JanusAdmin::Answer& made) {
                state->creating.erase(m.id);
                auto again = state->mountpoints.find(id);
                if (again == state->mountpoints.end() || again->second.id != m.id) {
                  // Its session ended meanwhile (its destroy may have come
                  // first, and found none): what Janus made, or may have, goes.
                  if (made.error.empty()) return destroy(*state, m);
                  if (made.unanswered) keep_stray(*state, m, StrayMountpoint::Origin::unanswered);
                  return record_mountpoints(*state);
                }
                again->second.recreating = {};
                if (!made.error.empty())
                  log(Level::warning, "broadcast " + id + ": mountpoint not created again: " + made.error);
                else
                  log(Level::info, "broadcast " + id + ": mountpoint " + std::to_string(again->second.id) + " is back");
              });
        });
  }
}

}  // namespace caustic::server
