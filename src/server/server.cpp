// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/server/server.hpp"

#include "h264_level.hpp"
#include "http_util.hpp"
#include "log.hpp"
#include "main_queue.hpp"
#include "notify.hpp"
#include "server_state.hpp"

#include "caustic/gl_context.hpp"

#include <glib-unix.h>
#include <gst/gst.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <thread>

namespace caustic::server {

struct Server::State {
  ServerState shared;
  GMainLoop* loop = nullptr;
  guint reaper = 0, sigint = 0, sigterm = 0, sighup = 0, watchdog = 0, drain = 0, broadcasts = 0;
  std::chrono::steady_clock::time_point drain_deadline;
  std::function<ServerConfig()> reloader;
  // The gallery is re-read (meshes, thumbnails: seconds on a CPU) on a
  // thread of its own, so requests and pings go on meanwhile.
  std::thread gallery_loader;
  std::atomic<bool> loader_cancel{false};
  bool reload_again = false;
  std::shared_ptr<State*> alive = std::make_shared<State*>(this);
  Server* owner = nullptr;
};

namespace {
constexpr unsigned long long kDrainCloseS = 30;  // a drain's end: closing the sessions left, at most
void log_config_warnings(const ServerConfig& c) {  // its own, and what H.264 cannot hold
  for (const auto& warning : c.warnings) log(Level::warning, warning);
  if (const auto w = h264_level_warning(c.width, c.height, c.framerate, c.bitrate_kbps); !w.empty()) log(Level::warning, w);
}

std::shared_ptr<const Gallery> load_checked_gallery(const std::filesystem::path& dir,
                                                   const std::atomic<bool>* cancel = nullptr) {
  auto gallery = std::make_shared<Gallery>(load_gallery(dir, 256, cancel));
  for (const auto& problem : gallery->problems) log(Level::warning, "scene skipped: " + problem);
  if (gallery->entries.empty()) throw ConfigError("scenes_dir: no usable scene in " + dir.string());
  return gallery;
}

std::string status_line(const ServerState& s) {
  return std::string("STATUS=") + (s.draining ? "draining: " : "") + std::to_string(s.sessions.size()) + " sessions, " + std::to_string(s.gallery->entries.size()) +
         " scenes, " + s.renderer;
}

// Ends the sessions whose viewer never connected, went away, or stopped
// showing signs of life (a frozen tab, a socket that never answers).
void reap(ServerState& st) {
  const auto now = std::chrono::steady_clock::now();
  std::vector<std::pair<std::string, std::string>> doomed;
  for (const auto& [id, session] : st.sessions) {
    if (!session->connected() && now - session->idle_since() > std::chrono::seconds(st.config.idle_timeout_s))
      doomed.emplace_back(id, "idle: no viewer connected");
    else if (session->broadcast() &&
             now - session->last_sign_of_life() > std::chrono::seconds(st.config.broadcast_timeout_s))
      doomed.emplace_back(id, "silent: the presenter sent nothing for " +
                                  std::to_string(st.config.broadcast_timeout_s) + " s");
    else if (!session->broadcast() && session->connected() &&
             now - session->last_sign_of_life() > std::chrono::seconds(st.config.viewer_timeout_s))
      doomed.emplace_back(id, "silent: the viewer showed no sign of life for " +
                                  std::to_string(st.config.viewer_timeout_s) + " s (" + session->last_media_said() +
                                  ")");
  }
  for (const auto& [id, why] : doomed) {
    ++st.metrics.sessions_reclaimed;
    st.end_session(id, why);
  }
}

// True when every session's render thread came round its loop recently: one
// stuck in a render (a hung GPU, a driver deadlock) withholds the ping. A
// session whose viewer takes no frames still passes: its render thread
// keeps looking at the parameters.
bool sessions_alive(const ServerState& s) {
  const auto now = std::chrono::steady_clock::now();
  for (const auto& [id, session] : s.sessions)
    if (auto beat = session->render_heartbeat(); beat && now - *beat > std::chrono::seconds(s.config.stall_timeout_s)) {
      log(Level::error,
          "session " + id + ": render thread stuck for over " + std::to_string(s.config.stall_timeout_s) +
              " s; withholding the watchdog ping",
          session->log_context());
      return false;
    }
  return true;
}

}  // namespace

Server::Server(ServerConfig config, std::filesystem::path data_dir) : state_(std::make_unique<State>()) {
  state_->owner = this;
  // First of all: SIGHUP's default action ends the process, and loading the
  // gallery can take a minute. One that comes meanwhile waits for the main
  // loop and reloads then (the configuration may have changed since it was read).
  state_->sighup = g_unix_signal_add_full(
      G_PRIORITY_DEFAULT, SIGHUP,
      [](gpointer data) -> gboolean {
        // A server whose start failed is gone; one not listening yet (were
        // the loop to turn during the start) has nothing to reload.
        if (auto state = static_cast<std::weak_ptr<State*>*>(data)->lock())
          if ((*state)->shared.listener) (*state)->owner->reload();
        return G_SOURCE_CONTINUE;
      },
      new std::weak_ptr<State*>(state_->alive), [](gpointer data) { delete static_cast<std::weak_ptr<State*>*>(data); });
  auto& s = state_->shared;
  s.config = std::move(config);
  s.api_policy = allow_connect(kContentSecurityPolicy, s.config.janus_ws_url);
  s.data_dir = std::move(data_dir);
  set_log_level(level_from_name(s.config.log_level));
  log_config_warnings(s.config);
  // Read by every GL context the process creates, before the first exists.
  if (s.config.egl_device >= 0) setenv("CAUSTICD_EGL_DEVICE", std::to_string(s.config.egl_device).c_str(), 1);
  // A GPU asked for and not there is a configuration error, said as such:
  // the gallery would otherwise fail every scene and blame the scenes folder.
  if (s.config.egl_device >= 0 || std::getenv("CAUSTICD_EGL_PLATFORM")) {
    try {
      GlContext probe(egl_platform_from_environment());
    } catch (const GlContextError& e) {
      throw ConfigError(std::string(s.config.egl_device >= 0 ? "egl_device: " : "CAUSTICD_EGL_PLATFORM: ") + e.what());
    }
  }
  if (!s.config.janus_admin_url.empty()) {
    check_broadcast_keys(s.config);
    s.janus = std::make_unique<JanusAdmin>(s.config.janus_admin_url, s.config.janus_admin_secret,
                                           s.config.janus_streaming_key);
    destroy_leftover_mountpoints(s);  // those a killed run left in Janus
  }
  auto gallery = load_checked_gallery(scenes_folder(s.config, s.data_dir));
  s.renderer = gallery->renderer;
  s.gallery = std::move(gallery);
  const auto designs = state_folder(s.config) / "designs";
  try {
    s.designs = std::make_unique<DesignJobs>(
        DesignSettings{designs, s.config.design_queue, s.config.design_workers, s.config.design_resolution,
                       s.config.design_expiry_s, s.config.design_max_stored},
        design_backend());
  } catch (const std::exception& e) {
    // The gallery still streams; uploads answer that designs cannot be stored.
    log(Level::warning, "designs are off: cannot use " + designs.string() + ": " + e.what());
  }
  // Paths stay percent-encoded (request_path()): decoded, "%2F" would be a
  // separator, and a file's "%25" would be decoded again by the file server.
  s.soup = soup_server_new("server-header", "causticd", "raw-paths", TRUE, nullptr);
  g_signal_connect(s.soup, "request-started", G_CALLBACK(on_request_started), &s);
  g_signal_connect(s.soup, "request-read", G_CALLBACK(on_request_read), &s);
  s.listener = std::make_unique<Listener>(s.soup, s.metrics, listener_limits(s.config));
  // The same path also carries plain requests (POST, and everything under
  // /api/v1/sessions/{id}): a handler entry with both callbacks takes both.
  // With an instance number, its prefixed path too (instance.hpp).
  std::vector<std::string> session_paths = {"/api/v1/sessions"};
  if (s.config.instance_index > 0) session_paths.push_back(url_prefix(s.config) + "/api/v1/sessions");
  for (const std::string& sessions : session_paths) {
    soup_server_add_websocket_handler(s.soup, sessions.c_str(), nullptr, nullptr, handle_signal_socket, &s, nullptr);
    soup_server_add_handler(s.soup, sessions.c_str(), handle_http, &s, nullptr);
  }
  soup_server_add_handler(s.soup, nullptr, handle_http, &s, nullptr);
  state_->loop = g_main_loop_new(nullptr, FALSE);
}

Server::~Server() {
  auto& s = state_->shared;
  state_->alive.reset();
  state_->loader_cancel = true;
  if (state_->gallery_loader.joinable()) state_->gallery_loader.join();
  end_all_broadcasts(s);
  std::vector<std::weak_ptr<Session>> closing;
  for (auto& [id, session] : s.sessions) {
    session->close("server shutting down");
    closing.push_back(session);
  }
  s.sessions.clear();
  for (guint source : {state_->reaper, state_->sigint, state_->sigterm, state_->sighup, state_->watchdog, state_->drain,
                       state_->broadcasts})
    if (source) g_source_remove(source);
  s.agent.reset();
  s.listener.reset();
  if (s.soup) {
    soup_server_disconnect(s.soup);
    g_object_unref(s.soup);
  }
  // Let the sessions' last callbacks run before the loop goes. A library
  // thread (ICE's) may hold a session a moment longer; its deletion comes
  // back to this loop (Session::start): wait for it, bounded.
  const auto left = [&] {
    return std::any_of(closing.begin(), closing.end(), [](const auto& w) { return !w.expired(); });
  };
  for (int i = 0; i == 0 || (left() && i < 200); ++i) {
    while (g_main_context_iteration(nullptr, FALSE)) {
    }
    if (left()) g_usleep(10000);
  }
  g_main_loop_unref(state_->loop);
}

std::string Server::listen() {
  auto& s = state_->shared;
  // The setting in the way named, for the journal: a restart may mend it.
  const auto naming = [](const char* port_key, auto&& bind) {
    try {
      return bind();
    } catch (const ListenError& e) {
      throw std::runtime_error(std::string(e.port ? port_key : "bind_address") + ": " + e.what());
    }
  };
  const std::string url = naming("port", [&] { return s.listener->listen(s.config.bind_address, s.config.port); });
  if (s.config.agent_port > 0)
    s.agent = naming("agent_port",
                     [&] { return std::make_unique<CapacityAgent>(s, s.config.bind_address, s.config.agent_port); });
  return url;
}

void Server::run() {
  auto& s = state_->shared;
  // Reclaim sessions whose viewer never connected, went away, or stopped
  // showing signs of life (a frozen tab, a socket that never answers).
  state_->reaper = g_timeout_add_seconds(
      1,
      [](gpointer data) -> gboolean {
        reap(*static_cast<ServerState*>(data));
        return G_SOURCE_CONTINUE;
      },
      &s);
  if (s.janus)
    state_->broadcasts = g_timeout_add_seconds(
        2,
        [](gpointer data) -> gboolean {
          check_broadcasts(*static_cast<ServerState*>(data));
          return G_SOURCE_CONTINUE;
        },
        &s);
  // The first SIGTERM or SIGINT drains (running sessions go on, new ones
  // are refused, a proxy sends them elsewhere) for up to drain_timeout_s;
  // the next one, or the last session ending, stops.
  auto stop = [](gpointer data) -> gboolean {
    auto& st = *static_cast<State*>(data);
    ServerState& s = st.shared;
    // A broadcast still waiting for Janus counts: its answer is awaited (and
    // its mountpoint removed), or Janus would keep one no one removes.
    if (s.draining || s.sessions_taken() == 0 || s.config.drain_timeout_s == 0) {
      notify("STOPPING=1");
      log(Level::notice, s.sessions_taken() == 0 ? "stopping" : "stopping: closing every session");
      g_main_loop_quit(st.loop);
      return G_SOURCE_CONTINUE;
    }
    s.draining = true;
    st.drain_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(s.config.drain_timeout_s);
    // systemd extends the unit's TimeoutStopSec by the drain and its close:
    notify("STOPPING=1\n" + status_line(s) + "\nEXTEND_TIMEOUT_USEC=" +
           std::to_string((s.config.drain_timeout_s + kDrainCloseS) * 1000000ull));
    log(Level::notice, "draining: no new sessions; the " + std::to_string(s.sessions.size()) +
                           " running go on for at most " + std::to_string(s.config.drain_timeout_s) +
                           " s (a second signal stops at once)");
    st.drain = g_timeout_add(
        250,
        [](gpointer data) -> gboolean {
          auto& st = *static_cast<State*>(data);
          const auto left = static_cast<std::size_t>(st.shared.sessions_taken());
          if (left > 0 && std::chrono::steady_clock::now() < st.drain_deadline) return G_SOURCE_CONTINUE;
          log(Level::notice, left > 0 ? "drain timeout: closing the " + std::to_string(left) + " sessions left"
                                      : "drained: every session has ended");
          g_main_loop_quit(st.loop);
          st.drain = 0;
          return G_SOURCE_REMOVE;
        },
        &st);
    return G_SOURCE_CONTINUE;
  };
  state_->sigint = g_unix_signal_add(SIGINT, stop, state_.get());
  state_->sigterm = g_unix_signal_add(SIGTERM, stop, state_.get());
  if (const auto interval = watchdog_interval()) {
    // Ping at half the interval systemd waits, from the main loop: a blocked
    // loop misses pings as surely as a stalled session withholds them.
    const auto period = std::max<long long>(1, std::chrono::duration_cast<std::chrono::milliseconds>(*interval).count() / 2);
    state_->watchdog = g_timeout_add(
        static_cast<guint>(period),
        [](gpointer data) -> gboolean {
          auto& st = *static_cast<ServerState*>(data);
          // A listener that cannot accept (no descriptors left) is as dead
          // to its clients as a stalled loop: let systemd restart it.
          if (sessions_alive(st) && st.listener->accepting()) notify("WATCHDOG=1\n" + status_line(st));
          return G_SOURCE_CONTINUE;
        },
        &s);
    log(Level::info, "watchdog: pinging every " + std::to_string(period) + " ms");
  }
  // The HTTP server listens and the gallery's GL context rendered every
  // thumbnail: the service is ready.
  notify("READY=1\n" + status_line(s));
  g_main_loop_run(state_->loop);
}

void Server::set_config_reloader(std::function<ServerConfig()> reload) { state_->reloader = std::move(reload); }

void Server::reload() {
  auto& s = state_->shared;
  notify_reloading();
  log(Level::notice, "reloading the configuration and the gallery");
  if (state_->reloader) {
    try {
      ServerConfig next = state_->reloader();
      check_config(next, s.data_dir);
      log_config_warnings(next);
      // Read once, at the start: the listener, the GPU, the design queue,
      // Janus's admin client. A reload keeps them and names each one
      // written anew.
      std::string kept;
      const auto keep = [&](const char* key, auto ServerConfig::*field) {
        if (next.*field == s.config.*field) return;
        next.*field = s.config.*field;
        kept += (kept.empty() ? "" : ", ") + std::string(key);
      };
      keep("bind_address", &ServerConfig::bind_address);
      keep("port", &ServerConfig::port);
      keep("egl_device", &ServerConfig::egl_device);
      keep("instance_index", &ServerConfig::instance_index);
      keep("agent_port", &ServerConfig::agent_port);
      keep("state_dir", &ServerConfig::state_dir);
      keep("design_queue", &ServerConfig::design_queue);
      keep("design_workers", &ServerConfig::design_workers);
      keep("design_resolution", &ServerConfig::design_resolution);
      keep("design_expiry_s", &ServerConfig::design_expiry_s);
      keep("design_max_stored", &ServerConfig::design_max_stored);
      keep("janus_admin_url", &ServerConfig::janus_admin_url);
      keep("janus_admin_secret", &ServerConfig::janus_admin_secret);
      keep("janus_streaming_key", &ServerConfig::janus_streaming_key);
      if (!kept.empty()) log(Level::warning, "kept as they were until the next restart: " + kept);
      s.config = std::move(next);
      s.api_policy = allow_connect(kContentSecurityPolicy, s.config.janus_ws_url);
      set_log_level(level_from_name(s.config.log_level));
    } catch (const std::exception& e) {
      // ConfigError, or what a folder check met (a permission, an I/O
      // error): on the main loop nothing may escape into GLib.
      log(Level::error, std::string("reload: the configuration is kept: ") + e.what());
    }
  }
  s.listener->set_limits(listener_limits(s.config));
  try {
    start_gallery_reload();
  } catch (const std::exception& e) {  // no thread to be had
    log(Level::error, std::string("reload: the gallery is kept: ") + e.what());
    notify("READY=1\n" + status_line(s));
  }
}

void Server::start_gallery_reload() {
  auto& st = *state_;
  if (st.gallery_loader.joinable()) {
    st.reload_again = true;  // the one running may have read the folder already
    return;
  }
  const auto dir = scenes_folder(st.shared.config, st.shared.data_dir);
  std::weak_ptr<State*> owner = st.alive;
  const std::atomic<bool>* cancel = &st.loader_cancel;
  st.gallery_loader = std::thread([dir, owner, cancel] {
    auto result = std::make_shared<std::pair<std::shared_ptr<const Gallery>, std::string>>();
    try {
      result->first = load_checked_gallery(dir, cancel);
    } catch (const std::exception& e) {
      result->second = e.what();
    }
    // Back on the main loop: swap the gallery in (running sessions keep
    // their own entries) and tell systemd the reload is over.
    auto* job = new std::pair<std::weak_ptr<State*>, decltype(result)>(owner, result);
    queue_on(
        nullptr,
        [](gpointer data) -> gboolean {
          auto* j = static_cast<std::pair<std::weak_ptr<State*>, decltype(result)>*>(data);
          auto state = j->first.lock();
          if (!state) return G_SOURCE_REMOVE;
          State& st = **state;
          if (st.gallery_loader.joinable()) st.gallery_loader.join();
          if (j->second->first) {
            st.shared.gallery = j->second->first;
            log(Level::info, "gallery reloaded: " + std::to_string(st.shared.gallery->entries.size()) + " scenes");
          } else if (!st.loader_cancel) {
            log(Level::error, "reload: the gallery is kept: " + j->second->second);
          }
          if (st.reload_again && !st.loader_cancel) {
            st.reload_again = false;
            st.owner->start_gallery_reload();
            return G_SOURCE_REMOVE;
          }
          notify("READY=1\n" + status_line(st.shared));
          return G_SOURCE_REMOVE;
        },
        job, [](gpointer data) { delete static_cast<std::pair<std::weak_ptr<State*>, decltype(result)>*>(data); });
  });
}

void Server::quit() { g_main_loop_quit(state_->loop); }

}  // namespace caustic::server
