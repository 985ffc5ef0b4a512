// SPDX-License-Identifier: LGPL-2.1-or-later
#include "janus_admin.hpp"

#include "caustic/json_text.hpp"
#include "log.hpp"

#include <algorithm>

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
  const std::string text = dump_json(body);  // never throws (invalid UTF-8 replaced): the callers count on an answer
  GBytes* bytes = g_bytes_new(text.data(), text.size());
  soup_message_set_request_body_from_bytes(msg, "application/json", bytes);
  g_bytes_unref(bytes);
  return msg;
}

JanusAdmin::Answer JanusAdmin::read_answer(SoupMessage* msg, GBytes* reply, GError* error) {
  Answer answer;
  if (error) {
    answer.error = std::string("Janus does not answer: ") + error->message;
    // Refused or unreachable: nothing reached Janus.
    answer.unanswered = !g_error_matches(error, G_IO_ERROR, G_IO_ERROR_CONNECTION_REFUSED) &&
                        !g_error_matches(error, G_IO_ERROR, G_IO_ERROR_HOST_UNREACHABLE) &&
                        !g_error_matches(error, G_IO_ERROR, G_IO_ERROR_NETWORK_UNREACHABLE);
  } else if (soup_message_get_status(msg) != SOUP_STATUS_OK) {
    answer.error = "Janus answered HTTP " + std::to_string(soup_message_get_status(msg));
  } else {
    gsize size = 0;
    const auto* text = reply ? static_cast<const char*>(g_bytes_get_data(reply, &size)) : nullptr;
    answer = parse_answer(std::string_view(text ? text : "", size));
  }
  return answer;
}

JanusAdmin::Answer JanusAdmin::parse_answer(std::string_view body) {
  // Read field by field with their types checked: this runs in a libsoup
  // callback, where an exception (a field of another type) would end the
  // process, whatever Janus (or what answers on its port) sends.
  const auto text_of = [](const nlohmann::json& j, const char* key) -> std::string {
    const auto it = j.find(key);
    return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  Answer answer;
  const auto json = parse_json_text(body);
  if (!json || !json->is_object()) {
    answer.error = "Janus answered something that is not a JSON object";
    return answer;
  }
  if (text_of(*json, "janus") != "success") {
    const auto error = json->find("error");
    const std::string reason = error != json->end() && error->is_object() ? text_of(*error, "reason") : "";
    answer.error = "Janus refused: " + (reason.empty() ? std::string("no reason given") : printable_name(reason, 200));
    return answer;
  }
  if (const auto response = json->find("response"); response != json->end() && response->is_object())
    answer.response = *response;
  else
    answer.response = nlohmann::json::object();
  if (const auto code = answer.response.find("error_code"); code != answer.response.end()) {
    answer.error_code = code->is_number_integer() ? code->get<int>() : -1;
    const std::string said = text_of(answer.response, "error");
    answer.error = said.empty() ? "the streaming plugin refused" : printable_name(said, 200);
  }
  return answer;
}

std::vector<JanusAdmin::Answer> JanusAdmin::plugin_requests_now(std::vector<nlohmann::json> requests, int timeout_s) {
  // On a context of their own, pushed for this thread: the loop's other
  // sources (requests, timers) do not run while the server stops.
  GMainContext* context = g_main_context_new();
  g_main_context_push_thread_default(context);
  // A connection each, so that all wait out one timeout together.
  const int conns = static_cast<int>(std::max<std::size_t>(requests.size(), 1));
  SoupSession* http =
      soup_session_new_with_options("timeout", timeout_s, "max-conns", conns, "max-conns-per-host", conns, nullptr);
  struct Call {
    SoupMessage* msg = nullptr;
    Answer answer;
    bool done = false;
  };
  std::vector<Call> calls(requests.size());
  for (std::size_t i = 0; i < requests.size(); ++i) {
    calls[i].msg = message(std::move(requests[i]));
    if (!calls[i].msg) {
      calls[i] = {nullptr, {{}, "not a URL: " + url_}, true};
      continue;
    }
    soup_session_send_and_read_async(
        http, calls[i].msg, G_PRIORITY_DEFAULT, nullptr,
        [](GObject* source, GAsyncResult* result, gpointer data) {
          auto* call = static_cast<Call*>(data);
          GError* error = nullptr;
          GBytes* reply = soup_session_send_and_read_finish(SOUP_SESSION(source), result, &error);
          call->answer = read_answer(call->msg, reply, error);
          call->done = true;
          if (error) g_error_free(error);
          if (reply) g_bytes_unref(reply);
        },
        &calls[i]);
  }
  // Each ends within the session's timeout (an answer or an error).
  const auto all_done = [&] { return std::all_of(calls.begin(), calls.end(), [](const Call& c) { return c.done; }); };
  while (!all_done()) g_main_context_iteration(context, TRUE);
  std::vector<Answer> answers;
  for (Call& c : calls) {
    answers.push_back(std::move(c.answer));
    if (c.msg) g_object_unref(c.msg);
  }
  g_object_unref(http);
  g_main_context_pop_thread_default(context);
  g_main_context_unref(context);
  return answers;
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
        if (call->alive.expired()) return;
        try {  // nothing may escape into the library's C callback (an abort)
          call->done(answer);
        } catch (const std::exception& e) {
          log(Level::error, std::string("broadcast: Janus's answer not handled: ") + e.what());
        }
      },
      new Call{std::move(done), msg, alive_});
}

}  // namespace caustic::server
