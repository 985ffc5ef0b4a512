// SPDX-License-Identifier: LGPL-2.1-or-later
#include "http_util.hpp"

#include "request_head.hpp"
#include "uri_path.hpp"

#include "caustic/json_text.hpp"

#include <algorithm>
#include <cstring>

namespace caustic::server {

void reply_bytes(SoupServerMessage* msg, guint status, const std::string& content_type, const void* data,
                 std::size_t size) {
  soup_server_message_set_status(msg, status, status_phrase(status));
  SoupMessageHeaders* headers = soup_server_message_get_response_headers(msg);
  soup_message_headers_replace(headers, "Cache-Control", "no-store");
  soup_message_headers_replace(headers, "X-Content-Type-Options", "nosniff");
  soup_server_message_set_response(msg, content_type.c_str(), SOUP_MEMORY_COPY, static_cast<const char*>(data), size);
}

void reply_json(SoupServerMessage* msg, guint status, const nlohmann::json& body) {
  const std::string text = dump_json(body);
  reply_bytes(msg, status, "application/json", text.data(), text.size());
}

void reply_problem(SoupServerMessage* msg, Metrics& metrics, guint status, const std::string& detail,
                   const std::string& key) {
  ++metrics.http_errors;
  nlohmann::json body = {{"type", "about:blank"},
                         {"title", status_phrase(status)},
                         {"status", status},
                         {"detail", detail}};
  if (!key.empty()) body["key"] = key;
  const std::string text = dump_json(body);
  reply_bytes(msg, status, "application/problem+json", text.data(), text.size());
}

const char* request_query(SoupServerMessage* msg) {
  GUri* uri = soup_server_message_get_uri(msg);
  if (const char* query = g_uri_get_query(uri)) return query;
  const char* path = g_uri_get_path(uri);
  const char* mark = path ? std::strchr(path, '?') : nullptr;
  return mark ? mark + 1 : nullptr;
}

std::string request_path(SoupServerMessage* msg) {
  const char* raw = g_uri_get_path(soup_server_message_get_uri(msg));
  std::string path = raw ? raw : "";
  path.erase(std::min(path.find('?'), path.size()));  // a "?" in a path is the query's (request_query())
  return routed_path(path);
}

bool lists_tag(SoupServerMessage* msg, const char* header, const std::string& etag, bool weak) {
  const char* list = soup_message_headers_get_list(soup_server_message_get_request_headers(msg), header);
  if (!list) return false;
  gchar** tags = g_strsplit(list, ",", -1);
  bool match = false;
  for (gchar** t = tags; *t && !match; ++t) {
    std::string tag = g_strstrip(*t);
    if (weak && tag.rfind("W/", 0) == 0) tag.erase(0, 2);
    match = tag == etag || tag == "*";
  }
  g_strfreev(tags);
  return match;
}

std::string bearer_token(SoupServerMessage* msg) {
  const char* value = soup_message_headers_get_one(soup_server_message_get_request_headers(msg), "Authorization");
  if (!value) return "";
  const std::string text = value;
  if (text.size() < 8 || g_ascii_strncasecmp(text.c_str(), "Bearer ", 7) != 0) return "";
  const auto start = text.find_first_not_of(' ', 7);
  return start == std::string::npos ? "" : text.substr(start);
}

std::string client_address(SoupServerMessage* msg, const std::vector<std::string>& trusted_proxies) {
  const char* host = soup_server_message_get_remote_host(msg);
  if (!host) return "unknown";
  if (std::find(trusted_proxies.begin(), trusted_proxies.end(), host) == trusted_proxies.end()) return host;
  const char* forwarded =
      soup_message_headers_get_list(soup_server_message_get_request_headers(msg), "X-Forwarded-For");
  if (!forwarded) return host;
  std::string last = forwarded;
  last = last.substr(last.rfind(',') == std::string::npos ? 0 : last.rfind(',') + 1);
  last.erase(0, last.find_first_not_of(" \t"));
  last.erase(last.find_last_not_of(" \t") + 1);
  // Only an address: anything else would let a client choose its bucket.
  GInetAddress* parsed = g_inet_address_new_from_string(last.c_str());
  if (!parsed) return host;
  g_object_unref(parsed);
  return last;
}

std::string allow_connect(std::string policy, const std::string& url) {
  const auto scheme = url.find("://");
  if (scheme == std::string::npos) return policy;
  const std::string origin = url.substr(0, url.find('/', scheme + 3));
  const std::string connect = "connect-src 'self'";
  if (const auto at = policy.find(connect); at != std::string::npos) policy.insert(at + connect.size(), " " + origin);
  return policy;
}

bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

}  // namespace caustic::server
