// SPDX-License-Identifier: LGPL-2.1-or-later
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

/// The request's path as it was sent, still percent-encoded, with the
/// escapes of unreserved characters decoded and the others' hex digits in
/// upper case (RFC 3986 6.2.2). The library hands handlers its path decoded,
/// where "%2F" is a separator and a file's "%25" is decoded twice.
std::string request_path(SoupServerMessage* msg);

/// The request's query as sent (still encoded), or null when it has none.
/// Of an HTTP/1.0 request without Host the library keeps the whole target,
/// "?" and query, as the URI's path: request_path() and this split it.
const char* request_query(SoupServerMessage* msg);

/// Whether the request's `header` (If-Match, If-None-Match) lists `etag`
/// or "*". `weak`: a W/ tag matches its strong twin (If-None-Match's weak
/// comparison, RFC 9110 8.8.3.2); otherwise a W/ tag matches nothing.
bool lists_tag(SoupServerMessage* msg, const char* header, const std::string& etag, bool weak);

/// The bearer token of the request, or "" (the scheme is case-insensitive,
/// RFC 9110 11.1).
std::string bearer_token(SoupServerMessage* msg);
/// The client's IP address as text ("unknown" when the library has none).
/// From a peer in `trusted_proxies`, the last address of X-Forwarded-For
/// (the one that proxy added) instead: behind a proxy, limits per address
/// then count visitors, not the proxy.
std::string client_address(SoupServerMessage* msg, const std::vector<std::string>& trusted_proxies);

/// Pages load scripts, styles and images from this server only; the video
/// arrives over WebRTC and the viewer talks to the API and its WebSocket.
/// lil-gui sets inline styles, hence 'unsafe-inline' for styles alone, and
/// carries its icon font as a data: URI.
inline constexpr const char* kContentSecurityPolicy =
    "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
    "font-src 'self' data:; "
    "media-src 'self' blob: mediastream:; connect-src 'self'; object-src 'none'; base-uri 'none'; "
    "frame-ancestors 'none'; form-action 'self'";
/// `policy` that lets pages also connect to `url`'s origin (scheme, host,
/// port: the broadcast server's WebSocket API); unchanged for "" or a path.
std::string allow_connect(std::string policy, const std::string& url);
/// Compares in time independent of where the strings differ.
bool same_secret(const std::string& a, const std::string& b);

}  // namespace caustic::server
