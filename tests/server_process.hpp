// SPDX-License-Identifier: LGPL-2.1-or-later
// Starts `causticd serve` on a free loopback port for a test and talks HTTP
// to it. Traffic stays on 127.0.0.1; every wait is bounded.
#pragma once

#include <gio/gio.h>
#include <glib.h>
#include <gtest/gtest.h>
#include <libsoup/soup.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace caustic::testing {

class ServerProcess {
 public:
  /// `environment`: variables added to the test's own; `binary`: another
  /// causticd (an installed one); `wrapper`: a command that runs it (for
  /// example prlimit and its arguments).
  explicit ServerProcess(std::vector<std::string> extra_args = {},
                         std::vector<std::pair<std::string, std::string>> environment = {},
                         const std::string& binary = CAUSTICD_BINARY, const std::vector<std::string>& wrapper = {})
      : ServerProcess(extra_args, environment, binary, wrapper, true) {}
  /// A start that the test may try again (a port it named was taken by
  /// another process meanwhile): one that fails fails no test; url() is "".
  static std::unique_ptr<ServerProcess> try_start(const std::vector<std::string>& extra_args) {
    return std::unique_ptr<ServerProcess>(new ServerProcess(extra_args, {}, CAUSTICD_BINARY, {}, false));
  }

 private:
  ServerProcess(const std::vector<std::string>& extra_args,
                const std::vector<std::pair<std::string, std::string>>& environment, const std::string& binary,
                const std::vector<std::string>& wrapper, bool must_start) {
    std::vector<const char*> argv;
    for (const auto& w : wrapper) argv.push_back(w.c_str());
    for (const char* a : {binary.c_str(), "serve", "--port", "0", "--ice-address", "127.0.0.1"}) argv.push_back(a);
    for (const auto& a : extra_args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    GError* error = nullptr;
    GSubprocessLauncher* launcher = g_subprocess_launcher_new(G_SUBPROCESS_FLAGS_STDOUT_PIPE);
    // Designs are kept under the state folder: a test's go to a temporary
    // one of its own, never the user's (a test that names state_dir keeps it).
    if (gchar* tmp = g_dir_make_tmp("causticd-state-XXXXXX", nullptr)) {
      state_home_ = tmp;
      g_free(tmp);
      g_subprocess_launcher_setenv(launcher, "XDG_STATE_HOME", state_home_.c_str(), TRUE);
    }
    // A GLib critical (a reference released twice, a NULL handed to GObject)
    // is a bug: it stops the server, and the test fails where it happened.
    g_subprocess_launcher_setenv(launcher, "G_DEBUG", "fatal-criticals", TRUE);
    for (const auto& [key, value] : environment) g_subprocess_launcher_setenv(launcher, key.c_str(), value.c_str(), TRUE);
    process_ = g_subprocess_launcher_spawnv(launcher, argv.data(), &error);
    g_object_unref(launcher);
    if (!process_) {
      ADD_FAILURE() << error->message;
      g_error_free(error);
      return;
    }
    // The first line names the URL (the port the kernel picked), read with
    // a deadline: a server that hangs before it listens fails the test here
    // rather than holding it to ctest's timeout.
    const std::string text = first_line(120);
    const std::string prefix = "listening on ";
    if (text.rfind(prefix, 0) != 0) {
      if (must_start) ADD_FAILURE() << "server did not start: \"" << text << "\"";
      return;
    }
    url_ = text.substr(prefix.size());
    if (!url_.empty() && url_.back() == '/') url_.pop_back();
  }

 public:
  ~ServerProcess() {
    if (process_) stop();
    if (!state_home_.empty()) {
      std::error_code ec;
      std::filesystem::remove_all(state_home_, ec);
    }
  }

  /// SIGTERM; when running sessions keep the server draining (up to a
  /// minute), a second SIGTERM after a second, which stops it at once; a
  /// kill 10 s after that. A test's sessions end with it.
  void stop() {
    g_subprocess_send_signal(process_, SIGTERM);
    for (int i = 0; i < 20 && !finished(); ++i) g_usleep(50000);
    if (!finished()) g_subprocess_send_signal(process_, SIGTERM);
    for (int i = 0; i < 100 && !finished(); ++i) g_usleep(100000);
    if (!finished()) g_subprocess_force_exit(process_);
    g_subprocess_wait(process_, nullptr, nullptr);
    g_object_unref(process_);
    process_ = nullptr;
  }

  bool finished() {
    GMainContext* ctx = g_main_context_default();
    while (g_main_context_iteration(ctx, FALSE)) {
    }
    return g_subprocess_get_identifier(process_) == nullptr;  // no pid once it exited and was reaped
  }

  /// Waits up to `ms` for the process to end; its exit status, or -1 when
  /// it is still running (or ended by a signal).
  int wait_exit(int ms) {
    for (int waited = 0; waited < ms && !finished(); waited += 20) g_usleep(20000);
    if (!finished()) return -1;
    return g_subprocess_get_if_exited(process_) ? g_subprocess_get_exit_status(process_) : -1;
  }
  void signal(int number) { g_subprocess_send_signal(process_, number); }

  const std::string& url() const { return url_; }
  int port() const { return std::stoi(url_.substr(url_.rfind(':') + 1)); }
  GSubprocess* process() const { return process_; }
  /// The process id as text ("" once it exited).
  std::string pid() const {
    const char* id = process_ ? g_subprocess_get_identifier(process_) : nullptr;
    return id ? id : "";
  }

 private:
  // The process's first line of output, without its newline; what came
  // when it ended, or when `seconds` passed, otherwise.
  std::string first_line(int seconds) {
    auto* pipe = G_POLLABLE_INPUT_STREAM(g_subprocess_get_stdout_pipe(process_));
    const gint64 deadline = g_get_monotonic_time() + gint64{seconds} * G_USEC_PER_SEC;
    std::string text;
    while (g_get_monotonic_time() < deadline) {
      char c = 0;
      GError* error = nullptr;
      const gssize n = g_pollable_input_stream_read_nonblocking(pipe, &c, 1, nullptr, &error);
      if (n == 1) {
        if (c == '\n') return text;
        text += c;
        continue;
      }
      const bool waiting = error && g_error_matches(error, G_IO_ERROR, G_IO_ERROR_WOULD_BLOCK);
      if (error) g_error_free(error);
      if (!waiting) return text;  // the end of its output, or a read error
      g_usleep(10000);
    }
    return text + " (no line within " + std::to_string(seconds) + " s)";
  }

  GSubprocess* process_ = nullptr;
  std::string url_;
  std::string state_home_;
};

struct Response {
  guint status = 0;
  std::string body;
  std::string content_type;
  nlohmann::json json() const { return nlohmann::json::parse(body, nullptr, false); }
};

/// One synchronous HTTP request with a 10 s timeout.
inline Response http(const std::string& method, const std::string& url, const std::string& body = "",
                     const std::string& content_type = "application/json",
                     const std::vector<std::pair<std::string, std::string>>& headers = {}) {
  SoupSession* session = soup_session_new_with_options("timeout", 10, nullptr);
  SoupMessage* msg = soup_message_new(method.c_str(), url.c_str());
  Response r;
  if (!msg) {
    g_object_unref(session);
    ADD_FAILURE() << "bad URL " << url;
    return r;
  }
  for (const auto& [k, v] : headers) soup_message_headers_replace(soup_message_get_request_headers(msg), k.c_str(), v.c_str());
  if (!body.empty() || method == "POST" || method == "PATCH") {
    GBytes* bytes = g_bytes_new(body.data(), body.size());
    soup_message_set_request_body_from_bytes(msg, content_type.empty() ? nullptr : content_type.c_str(), bytes);
    g_bytes_unref(bytes);
  }
  GError* error = nullptr;
  GBytes* reply = soup_session_send_and_read(session, msg, nullptr, &error);
  if (error) {
    ADD_FAILURE() << method << " " << url << ": " << error->message;
    g_error_free(error);
  }
  r.status = soup_message_get_status(msg);
  if (reply) {
    gsize size = 0;
    const auto* data = static_cast<const char*>(g_bytes_get_data(reply, &size));
    r.body.assign(data, size);
    g_bytes_unref(reply);
  }
  if (const char* type = soup_message_headers_get_content_type(soup_message_get_response_headers(msg), nullptr))
    r.content_type = type;
  g_object_unref(msg);
  g_object_unref(session);
  return r;
}

/// The Authorization header of a session's holder (an answer of POST
/// /api/v1/sessions), or of any bearer token.
inline std::vector<std::pair<std::string, std::string>> bearer_token(const std::string& token) {
  return {{"Authorization", "Bearer " + token}};
}
inline std::vector<std::pair<std::string, std::string>> bearer(const nlohmann::json& session) {
  return bearer_token(session["token"].get<std::string>());
}

}  // namespace caustic::testing
