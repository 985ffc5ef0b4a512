// SPDX-License-Identifier: LGPL-2.1-or-later
#include "janus_admin.hpp"

namespace caustic::server {

JanusAdmin::JanusAdmin(std::string url, std::string admin_secret, std::string streaming_key, int timeout_s)
    : url_(std::move(url)), secret_(std::move(admin_secret)), key_(std::move(streaming_key)) {
  http_ = soup_session_new_with_options("timeout", timeout_s, "max-conns", 4, nullptr);
}

JanusAdmin::~JanusAdmin() {
  alive_.reset();
  soup_session_abort(http_);
  g_object_unref(http_);
}

SoupMessage* JanusAdmin::message(nlohmann::json request) {
  request["admin_key"] = key_;
  const nlohmann::json body = {{"janus", "message_plugin"},
                               {"transaction", "causticd-" + std::to_string(++transaction_)},
                               {"admin_secret", secret_},
                               {"plugin", "janus.plugin.streaming"},
                               {"request", std::move(request)}};
  SoupMessage* msg = soup_message_new("POST", url_.c_str());
  if (!msg) return nullptr;
  const std::string text = body.dump();
  GBytes* bytes = g_bytes_new(text.data(), text.size());
  soup_message_set_request_body_from_bytes(msg, "application/json", bytes);
  g_bytes_unref(bytes);
  return msg;
}

JanusAdmin::Answer JanusAdmin::read_answer(SoupMessage* msg, GBytes* reply, GError* error) {
  Answer answer;
  if (error) {
    answer.error = std::string("Janus does not answer: ") + error->message;
  } else if (soup_message_get_status(msg) != SOUP_STATUS_OK) {
    answer.error = "Janus answered HTTP " + std::to_string(soup_message_get_status(msg));
  } else {
    gsize size = 0;
    const auto* text = static_cast<const char*>(g_bytes_get_data(reply, &size));
    const auto json = nlohmann::json::parse(text, text + size, nullptr, false);
    if (!json.is_object()) {
      answer.error = "Janus answered something that is not JSON";
    } else if (json.value("janus", "") != "success") {
      answer.error = "Janus refused: " + json.value("error", nlohmann::json::object()).value("reason", json.dump());
    } else {
      answer.response = json.value("response", nlohmann::json::object());
      if (answer.response.contains("error_code")) {
        answer.error_code = answer.response.value("error_code", 0);
        answer.error = answer.response.value("error", "the streaming plugin refused");
      }
    }
  }
  return answer;
}

JanusAdmin::Answer JanusAdmin::plugin_request_now(nlohmann::json request, int timeout_s) {
  SoupMessage* msg = message(std::move(request));
  if (!msg) return {{}, "not a URL: " + url_};
  SoupSession* http = soup_session_new_with_options("timeout", timeout_s, nullptr);
  GError* error = nullptr;
  GBytes* reply = soup_session_send_and_read(http, msg, nullptr, &error);
  Answer answer = read_answer(msg, reply, error);
  if (error) g_error_free(error);
  if (reply) g_bytes_unref(reply);
  g_object_unref(msg);
  g_object_unref(http);
  return answer;
}

void JanusAdmin::plugin_request(nlohmann::json request, Done done) {
  SoupMessage* msg = message(std::move(request));
  if (!msg) return done({{}, "not a URL: " + url_});
  struct Call {
    Done done;
    SoupMessage* msg;
    std::weak_ptr<bool> alive;
  };
  soup_session_send_and_read_async(
      http_, msg, G_PRIORITY_DEFAULT, nullptr,
      [](GObject* source, GAsyncResult* result, gpointer data) {
        std::unique_ptr<Call> call(static_cast<Call*>(data));
        GError* error = nullptr;
        GBytes* reply = soup_session_send_and_read_finish(SOUP_SESSION(source), result, &error);
        const Answer answer = read_answer(call->msg, reply, error);
        if (error) g_error_free(error);
        if (reply) g_bytes_unref(reply);
        g_object_unref(call->msg);
        if (!call->alive.expired()) call->done(answer);
      },
      new Call{std::move(done), msg, alive_});
}

}  // namespace caustic::server
