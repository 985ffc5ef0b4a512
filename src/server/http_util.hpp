// Small helpers for answering libsoup requests.
#pragma once

#include "metrics.hpp"

#include <libsoup/soup.h>
#include <nlohmann/json.hpp>

#include <string>

namespace caustic::server {

void reply_json(SoupServerMessage* msg, guint status, const nlohmann::json& body);
/// An RFC 9457 problem document; `key` names the offending field when there is one.
void reply_problem(SoupServerMessage* msg, Metrics& metrics, guint status, const std::string& detail,
                   const std::string& key = "");
void reply_bytes(SoupServerMessage* msg, guint status, const std::string& content_type, const void* data,
                 std::size_t size);

/// The bearer token of the request, or "".
std::string bearer_token(SoupServerMessage* msg);
/// Compares in time independent of where the strings differ.
bool same_secret(const std::string& a, const std::string& b);

}  // namespace caustic::server
