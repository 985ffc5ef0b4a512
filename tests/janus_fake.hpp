// SPDX-License-Identifier: LGPL-2.1-or-later
// A stand-in for Janus's admin API, for what a real Janus cannot be made to
// do on cue: hold one answer while others are given. A libsoup server on
// loopback, on a thread and main context of its own; it records every
// request, and a script says, for each, its answer or that it is held until
// the test answers it.
#pragma once

#include <glib.h>
#include <gtest/gtest.h>
#include <libsoup/soup.h>
#include <nlohmann/json.hpp>
#include <poll.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace caustic::testing {

class FakeJanus {
 public:
  using json = nlohmann::json;
  /// For a streaming plugin request (the admin message's "request"): the
  /// plugin's "response", or nothing to hold it. Runs on the fake's thread.
  using Script = std::function<std::optional<json>(const json& request)>;

  explicit FakeJanus(Script script) : script_(std::move(script)) {
    std::mutex started;
    std::condition_variable ready;
    bool up = false;
    thread_ = std::thread([&] {
      g_main_context_push_thread_default(context_);
      server_ = soup_server_new(nullptr, nullptr);
      soup_server_add_handler(server_, "/admin", &FakeJanus::handle, this, nullptr);
      GError* error = nullptr;
      if (soup_server_listen_local(server_, 0, SOUP_SERVER_LISTEN_IPV4_ONLY, &error)) {
        GSList* uris = soup_server_get_uris(server_);
        url_ = "http://127.0.0.1:" + std::to_string(g_uri_get_port(static_cast<GUri*>(uris->data))) + "/admin";
        g_slist_free_full(uris, reinterpret_cast<GDestroyNotify>(g_uri_unref));
      } else {
        g_error_free(error);
      }
      {
        std::lock_guard lock(started);
        up = true;
      }
      ready.notify_all();
      if (!url_.empty()) g_main_loop_run(loop_);
      soup_server_disconnect(server_);
      for (Request& r : requests_)
        if (r.held) g_object_unref(r.held);
      g_object_unref(server_);
      g_main_context_pop_thread_default(context_);
    });
    std::unique_lock lock(started);
    ready.wait(lock, [&] { return up; });
  }
  ~FakeJanus() {
    g_main_context_invoke(context_, +[](gpointer loop) -> gboolean {
      g_main_loop_quit(static_cast<GMainLoop*>(loop));
      return G_SOURCE_REMOVE;
    }, loop_);
    thread_.join();
    g_main_loop_unref(loop_);
    g_main_context_unref(context_);
  }
  FakeJanus(const FakeJanus&) = delete;
  FakeJanus& operator=(const FakeJanus&) = delete;

  /// The admin URL ("" if it could not listen).
  const std::string& url() const { return url_; }

  /// The index of the first request from the `from`th on that `match`
  /// takes, waiting up to `seconds` for it; -1 if none came.
  int wait_for(std::size_t from, const std::function<bool(const json&)>& match, int seconds = 20) {
    std::unique_lock lock(mutex_);
    int found = -1;
    changed_.wait_for(lock, std::chrono::seconds(seconds), [&] {
      for (std::size_t i = from; i < requests_.size() && found < 0; ++i)
        if (match(requests_[i].request)) found = static_cast<int>(i);
      return found >= 0;
    });
    return found;
  }
  json request(int i) {
    std::lock_guard lock(mutex_);
    return requests_.at(static_cast<std::size_t>(i)).request;
  }
  /// Whether the client gave up on held request `i` (closed its
  /// connection) before the test answered it.
  bool abandoned(int i) {
    std::lock_guard lock(mutex_);
    const Request& r = requests_.at(static_cast<std::size_t>(i));
    return r.abandoned || (r.held && closed(r.held));
  }

  /// Gives held request `i` the plugin's `response`.
  void answer(int i, json response) {
    struct Answer {
      FakeJanus* self;
      int i;
      json response;
    };
    g_main_context_invoke_full(context_, G_PRIORITY_DEFAULT, +[](gpointer data) -> gboolean {
      const auto* a = static_cast<Answer*>(data);
      SoupServerMessage* held = nullptr;
      std::string transaction;
      bool abandoned = false;
      {
        // Taken from the record first: replying may emit its signals.
        std::lock_guard lock(a->self->mutex_);
        Request& r = a->self->requests_.at(static_cast<std::size_t>(a->i));
        std::swap(held, r.held);
        transaction = r.transaction;
        abandoned = r.abandoned = held && closed(held);
      }
      if (held && !abandoned) {
        reply(held, transaction, a->response);
        soup_server_message_unpause(held);
      }
      if (held) g_object_unref(held);
      return G_SOURCE_REMOVE;
    }, new Answer{this, i, std::move(response)}, +[](gpointer data) { delete static_cast<Answer*>(data); });
  }

 private:
  struct Request {
    json request;
    std::string transaction;
    SoupServerMessage* held = nullptr;
    bool abandoned = false;
  };

  // A held request's connection, unread while it is paused, shows the
  // client's close at once.
  static bool closed(SoupServerMessage* msg) {
    GSocket* socket = soup_server_message_get_socket(msg);
    pollfd p{socket ? g_socket_get_fd(socket) : -1, POLLRDHUP, 0};
    return !socket || (::poll(&p, 1, 0) == 1 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)));
  }

  static void reply(SoupServerMessage* msg, const std::string& transaction, const json& response) {
    const std::string body = json{{"janus", "success"}, {"transaction", transaction}, {"response", response}}.dump();
    soup_server_message_set_status(msg, SOUP_STATUS_OK, nullptr);
    soup_server_message_set_response(msg, "application/json", SOUP_MEMORY_COPY, body.data(), body.size());
  }

  static void handle(SoupServer*, SoupServerMessage* msg, const char*, GHashTable*, gpointer data) {
    auto* self = static_cast<FakeJanus*>(data);
    SoupMessageBody* body = soup_server_message_get_request_body(msg);
    const json message = json::parse(std::string(body->data ? body->data : "", body->length), nullptr, false);
    // Fields of other types read as absent: the script sees an object.
    const auto field = [&](const char* key) { return message.is_object() && message.contains(key) ? message[key] : json(); };
    Request r;
    r.request = field("request").is_object() ? field("request") : json::object();
    r.transaction = field("transaction").is_string() ? field("transaction").get<std::string>() : "";
    const std::optional<json> response = self->script_(r.request);
    if (response) reply(msg, r.transaction, *response);
    std::lock_guard lock(self->mutex_);
    if (!response) {
      r.held = SOUP_SERVER_MESSAGE(g_object_ref(msg));
      soup_server_message_pause(msg);
    }
    self->requests_.push_back(std::move(r));
    self->changed_.notify_all();
  }

  Script script_;
  GMainContext* context_ = g_main_context_new();
  GMainLoop* loop_ = g_main_loop_new(context_, FALSE);
  SoupServer* server_ = nullptr;
  std::thread thread_;
  std::string url_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Request> requests_;
};

}  // namespace caustic::testing
