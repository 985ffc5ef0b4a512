#include "caustic/server/server.hpp"

#include "log.hpp"
#include "notify.hpp"
#include "server_state.hpp"

#include <glib-unix.h>
#include <gst/gst.h>

#include <cstdlib>

namespace caustic::server {

void ServerState::end_session(const std::string& id, const std::string& reason) {
  auto it = sessions.find(id);
  if (it == sessions.end()) return;
  // Keep the session alive until the main loop is back at the top: this may
  // run inside one of its own callbacks.
  auto* doomed = new std::shared_ptr<Session>(it->second);
  sessions.erase(it);
  log(Level::info, "session " + id + " ended: " + reason);
  (*doomed)->close(reason);
  g_idle_add_full(
      G_PRIORITY_DEFAULT_IDLE, [](gpointer) -> gboolean { return G_SOURCE_REMOVE; }, doomed,
      [](gpointer data) { delete static_cast<std::shared_ptr<Session>*>(data); });
}

struct Server::State {
  ServerState shared;
  GMainLoop* loop = nullptr;
  guint reaper = 0, sigint = 0, sigterm = 0, sighup = 0, watchdog = 0;
  std::function<ServerConfig()> reloader;
};

namespace {

std::shared_ptr<const Gallery> load_checked_gallery(const ServerState& s) {
  const auto dir = scenes_folder(s.config, s.data_dir);
  auto gallery = std::make_shared<Gallery>(load_gallery(dir));
  for (const auto& problem : gallery->problems) log(Level::warning, "scene skipped: " + problem);
  if (gallery->entries.empty()) throw std::runtime_error("no usable scene in " + dir.string());
  return gallery;
}

std::string status_line(const ServerState& s) {
  return "STATUS=" + std::to_string(s.sessions.size()) + " sessions, " + std::to_string(s.gallery->entries.size()) +
         " scenes, " + s.renderer;
}

// True when every session's render thread came round its loop recently: one
// stuck in a render (a hung GPU, a driver deadlock) withholds the ping. A
// session whose viewer takes no frames still passes: its render thread
// keeps looking at the parameters.
bool sessions_alive(const ServerState& s) {
  const auto now = std::chrono::steady_clock::now();
  for (const auto& [id, session] : s.sessions)
    if (auto beat = session->render_heartbeat(); beat && now - *beat > std::chrono::seconds(s.config.stall_timeout_s)) {
      log(Level::error, "session " + id + ": render thread stuck for over " + std::to_string(s.config.stall_timeout_s) +
                            " s; withholding the watchdog ping");
      return false;
    }
  return true;
}

}  // namespace

Server::Server(ServerConfig config, std::filesystem::path data_dir) : state_(std::make_unique<State>()) {
  auto& s = state_->shared;
  s.config = std::move(config);
  s.data_dir = std::move(data_dir);
  set_log_level(level_from_name(s.config.log_level));
  // Read by every GL context the process creates, before the first exists.
  if (s.config.egl_device >= 0) setenv("CAUSTICD_EGL_DEVICE", std::to_string(s.config.egl_device).c_str(), 1);
  auto gallery = load_checked_gallery(s);
  s.renderer = gallery->renderer;
  s.gallery = std::move(gallery);
  s.soup = soup_server_new("server-header", "causticd", nullptr);
  soup_server_add_early_handler(s.soup, nullptr, handle_early, &s, nullptr);
  soup_server_add_websocket_handler(s.soup, "/api/v1/sessions", nullptr, nullptr, handle_signal_socket, &s, nullptr);
  // The same path also carries plain requests (POST, and everything under
  // /api/v1/sessions/{id}): a handler entry with both callbacks takes both.
  soup_server_add_handler(s.soup, "/api/v1/sessions", handle_http, &s, nullptr);
  soup_server_add_handler(s.soup, nullptr, handle_http, &s, nullptr);
  state_->loop = g_main_loop_new(nullptr, FALSE);
}

Server::~Server() {
  auto& s = state_->shared;
  for (auto& [id, session] : s.sessions) session->close("server shutting down");
  s.sessions.clear();
  for (guint source : {state_->reaper, state_->sigint, state_->sigterm, state_->sighup, state_->watchdog})
    if (source) g_source_remove(source);
  if (s.soup) {
    soup_server_disconnect(s.soup);
    g_object_unref(s.soup);
  }
  // Let the sessions' last callbacks run before the loop goes.
  while (g_main_context_iteration(nullptr, FALSE)) {
  }
  g_main_loop_unref(state_->loop);
}

std::string Server::listen() {
  auto& s = state_->shared;
  GError* error = nullptr;
  GSocketAddress* address =
      g_inet_socket_address_new_from_string(s.config.bind_address.c_str(), static_cast<guint>(s.config.port));
  if (!address) throw std::runtime_error("cannot use bind address " + s.config.bind_address);
  const gboolean ok = soup_server_listen(s.soup, address, static_cast<SoupServerListenOptions>(0), &error);
  g_object_unref(address);
  if (!ok) {
    std::string message = error->message;
    g_error_free(error);
    throw std::runtime_error("cannot listen on " + s.config.bind_address + ":" + std::to_string(s.config.port) +
                             ": " + message);
  }
  GSList* uris = soup_server_get_uris(s.soup);
  std::string url = uris ? g_uri_to_string(static_cast<GUri*>(uris->data)) : "";
  g_slist_free_full(uris, reinterpret_cast<GDestroyNotify>(g_uri_unref));
  return url;
}

void Server::run() {
  auto& s = state_->shared;
  // Reclaim sessions whose viewer never connected or went away.
  state_->reaper = g_timeout_add_seconds(
      1,
      [](gpointer data) -> gboolean {
        auto& st = *static_cast<ServerState*>(data);
        const auto now = std::chrono::steady_clock::now();
        std::vector<std::string> idle;
        for (const auto& [id, session] : st.sessions)
          if (!session->connected() && now - session->idle_since() > std::chrono::seconds(st.config.idle_timeout_s))
            idle.push_back(id);
        for (const auto& id : idle) st.end_session(id, "idle: no viewer connected");
        return G_SOURCE_CONTINUE;
      },
      &s);
  auto quit = [](gpointer loop) -> gboolean {
    notify("STOPPING=1");
    log(Level::notice, "stopping: closing every session");
    g_main_loop_quit(static_cast<GMainLoop*>(loop));
    return G_SOURCE_CONTINUE;
  };
  state_->sigint = g_unix_signal_add(SIGINT, quit, state_->loop);
  state_->sigterm = g_unix_signal_add(SIGTERM, quit, state_->loop);
  state_->sighup = g_unix_signal_add(
      SIGHUP,
      [](gpointer self) -> gboolean {
        static_cast<Server*>(self)->reload();
        return G_SOURCE_CONTINUE;
      },
      this);
  if (const auto interval = watchdog_interval()) {
    // Ping at half the interval systemd waits, from the main loop: a blocked
    // loop misses pings as surely as a stalled session withholds them.
    const auto period = std::max<long long>(1, std::chrono::duration_cast<std::chrono::milliseconds>(*interval).count() / 2);
    state_->watchdog = g_timeout_add(
        static_cast<guint>(period),
        [](gpointer data) -> gboolean {
          auto& st = *static_cast<ServerState*>(data);
          if (sessions_alive(st)) notify("WATCHDOG=1\n" + status_line(st));
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
      if (next.bind_address != s.config.bind_address || next.port != s.config.port || next.egl_device != s.config.egl_device) {
        log(Level::warning, "bind_address, port and egl_device take effect at the next restart; kept as they are");
        next.bind_address = s.config.bind_address;
        next.port = s.config.port;
        next.egl_device = s.config.egl_device;
      }
      s.config = std::move(next);
      set_log_level(level_from_name(s.config.log_level));
    } catch (const ConfigError& e) {
      log(Level::error, std::string("reload: the configuration is kept: ") + e.what());
    }
  }
  try {
    s.gallery = load_checked_gallery(s);  // running sessions keep their own entries
    log(Level::info, "gallery reloaded: " + std::to_string(s.gallery->entries.size()) + " scenes");
  } catch (const std::exception& e) {
    log(Level::error, std::string("reload: the gallery is kept: ") + e.what());
  }
  notify("READY=1\n" + status_line(s));
}

void Server::quit() { g_main_loop_quit(state_->loop); }

}  // namespace caustic::server
