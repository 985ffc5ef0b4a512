// SPDX-License-Identifier: LGPL-2.1-or-later
// POST /api/v1/designs (a picture in, a design job out), GET and DELETE
// /api/v1/designs/{id}: docs/api.md. Everything a picture can be refused
// for is decided here, before it reaches the queue: who may upload, how
// often, its media type, its bytes and, from its header alone, its pixels.
#include "address_group.hpp"
#include "http_util.hpp"
#include "picture_header.hpp"
#include "server_state.hpp"

#include "caustic/jpeg_scans.hpp"
#include "caustic/json_text.hpp"
#include "caustic/shown_text.hpp"

#include <algorithm>
#include <regex>
#include <string>
#include <vector>

namespace caustic::server {
namespace {

constexpr const char* kDefaultName = "Your picture";
constexpr std::size_t kMaxNameBytes = 64;

// Uploads one address may make at once: a twentieth of the hourly
// allowance, at least 4 (a visitor trying a few pictures), at most all of it.
int upload_burst(int per_hour) { return std::min(per_hour, std::max(4, per_hour / 20)); }

// A query's parts between its '&'s (empty ones skipped).
std::vector<std::string> split_query(const std::string& query) {
  std::vector<std::string> parts;
  for (std::size_t start = 0; start <= query.size();) {
    const auto end = std::min(query.find('&', start), query.size());
    if (end > start) parts.push_back(query.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

// Form decoding ('+' a space, %XX a byte); a broken escape reads as written.
std::string unescape(std::string text) {
  std::replace(text.begin(), text.end(), '+', ' ');
  char* decoded = g_uri_unescape_string(text.c_str(), nullptr);
  if (!decoded) return text;
  std::string out = decoded;
  g_free(decoded);
  return out;
}

void refuse(ServerState& s, SoupServerMessage* msg, guint status, const std::string& detail,
            const std::string& key = "") {
  ++s.metrics.designs_refused;
  reply_problem(msg, s.metrics, status, detail, key);
}

// The name a visitor gives the design: printable, valid UTF-8, short. Empty
// when it is not, with `why` set.
bool valid_name(const std::string& name, std::string* why) {
  if (name.empty() || name.size() > kMaxNameBytes) {
    *why = "name: must be 1 to " + std::to_string(kMaxNameBytes) + " bytes";
    return false;
  }
  if (holds_control_characters(name)) {
    *why = "name: must not hold control characters";
    return false;
  }
  if (!g_utf8_validate(name.data(), static_cast<gssize>(name.size()), nullptr)) {
    *why = "name: must be UTF-8";
    return false;
  }
  return true;
}

void upload(ServerState& s, SoupServerMessage* msg) {
  SoupMessageHeaders* response = soup_server_message_get_response_headers(msg);
  if (!(s.designs ? s.designs->built_in() : design_backend().built_in))
    return refuse(s, msg, SOUP_STATUS_NOT_IMPLEMENTED, "design is not built into this server");
  // The state directory was unusable at the start (logged then): a fault
  // the operator mends, not something this server lacks (501).
  if (!s.designs) return refuse(s, msg, SOUP_STATUS_SERVICE_UNAVAILABLE, "this server cannot store designs now");
  if (!s.config.design_uploads) return refuse(s, msg, SOUP_STATUS_FORBIDDEN, "picture uploads are turned off here");
  if (!s.config.design_upload_token.empty() && !same_secret(bearer_token(msg), s.config.design_upload_token)) {
    soup_message_headers_replace(response, "WWW-Authenticate", "Bearer");
    return refuse(s, msg, SOUP_STATUS_UNAUTHORIZED, "uploading a picture needs this server's bearer token");
  }
  std::string name = kDefaultName;
  bool colour = false;
  std::string bad_colour;
  if (const char* query = request_query(msg)) {
    // Each key once and with a value: a form decoder keeps the last of a
    // repeated key and drops one without "=", both silently.
    std::vector<std::string> seen;
    for (const std::string& part : split_query(query)) {
      const auto eq = part.find('=');
      const std::string k = unescape(part.substr(0, eq)), v = eq == std::string::npos ? "" : unescape(part.substr(eq + 1));
      const std::string shown = printable_name(k);  // the client's bytes, made safe to echo
      if (k != "name" && k != "colour")
        return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY,
                      shown + ": unknown query key; the keys taken are \"name\" and \"colour\"", shown);
      if (std::find(seen.begin(), seen.end(), k) != seen.end())
        return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY, k + " is given twice", k);
      if (eq == std::string::npos) return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY, k + " needs a value", k);
      seen.push_back(k);
      if (k == "name") name = v;
      else if (v == "true" || v == "false") colour = v == "true";
      else bad_colour = "colour must be \"true\" or \"false\"";
    }
    if (!bad_colour.empty()) return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY, bad_colour, "colour");
  }
  std::string why;
  if (!valid_name(name, &why)) return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY, why, "name");

  const char* type = soup_message_headers_get_content_type(soup_server_message_get_request_headers(msg), nullptr);
  const bool png = type && g_ascii_strcasecmp(type, "image/png") == 0;
  const bool jpeg = type && g_ascii_strcasecmp(type, "image/jpeg") == 0;
  if (!png && !jpeg) return refuse(s, msg, SOUP_STATUS_UNSUPPORTED_MEDIA_TYPE, "the body must be image/png or image/jpeg");
  SoupMessageBody* body = soup_server_message_get_request_body(msg);
  if (body->length > static_cast<goffset>(s.config.design_max_upload_bytes))
    return refuse(s, msg, SOUP_STATUS_REQUEST_ENTITY_TOO_LARGE,
                  "the picture is larger than " + std::to_string(s.config.design_max_upload_bytes) + " bytes");
  const auto* bytes = reinterpret_cast<const unsigned char*>(body->data);
  const auto size = static_cast<std::size_t>(body->length);
  const PictureHeader header = read_picture_header(bytes, size);
  const auto declared = png ? PictureHeader::Format::png : PictureHeader::Format::jpeg;
  if (header.format != declared)
    return refuse(s, msg, SOUP_STATUS_UNSUPPORTED_MEDIA_TYPE, std::string("the body is not ") + media_type(declared));
  if (header.width == 0 || header.height == 0)
    return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY, "the picture's header gives no size: a broken file");
  const unsigned long long pixels = 1ULL * header.width * header.height;
  if (pixels > static_cast<unsigned long long>(s.config.design_max_pixels))
    return refuse(s, msg, SOUP_STATUS_REQUEST_ENTITY_TOO_LARGE,
                  "the picture has " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                      " pixels; at most " + std::to_string(s.config.design_max_pixels) + " are taken");
  if (header.width > s.designs->max_side() || header.height > s.designs->max_side())
    return refuse(s, msg, SOUP_STATUS_REQUEST_ENTITY_TOO_LARGE,
                  "the picture is " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                      " pixels; at most " + std::to_string(s.designs->max_side()) + " a side are taken");
  // A picture cut short has a whole header: its end says so before a queue
  // place and an upload of the hour are spent on it.
  if (!picture_complete(bytes, size, header.format))
    return refuse(s, msg, SOUP_STATUS_UNSUPPORTED_MEDIA_TYPE,
                  std::string("the body is not a whole ") + media_type(declared) + ": it ends before the picture does");
  // Each scan of a progressive JPEG is decoded anew: a few thousand held a
  // worker, and the queue behind it, for minutes (caustic/jpeg_scans.hpp).
  if (header.format == PictureHeader::Format::jpeg && jpeg_scans(bytes, size) > kMaxJpegScans)
    return refuse(s, msg, SOUP_STATUS_UNPROCESSABLE_ENTITY,
                  "the JPEG holds more than " + std::to_string(kMaxJpegScans) + " scans; save it as a baseline JPEG");
  // Charged only for a picture that would be designed: the designs are
  // what costs (refusals are cheap, and the general rate limit covers them).
  const std::string address = address_group(client_address(msg, s.config.trusted_proxies));
  if (!s.within(s.design_rate, msg, address, s.config.design_uploads_per_hour / 3600.0,
                upload_burst(s.config.design_uploads_per_hour),
                "your address may upload " + std::to_string(s.config.design_uploads_per_hour) + " pictures an hour")) {
    ++s.metrics.designs_refused;
    return;
  }
  DesignJobs::Ticket ticket;
  try {
    ticket = s.designs->submit(std::vector<unsigned char>(bytes, bytes + size), extension(header.format), name, colour);
  } catch (const DesignRefusal& e) {
    s.design_rate.refund(address);  // nothing will be designed: the upload of the hour is given back
    soup_message_headers_replace(response, "Retry-After", "30");
    return refuse(s, msg, e.status, e.what());
  }
  ++s.metrics.designs_submitted;
  // Kept by this instance: behind a proxy, its URL says so (instance.hpp).
  const std::string where = url_prefix(s.config) + "/api/v1/designs/" + ticket.id;
  soup_message_headers_replace(response, "Location", where.c_str());
  reply_json(msg, SOUP_STATUS_ACCEPTED,
             {{"id", ticket.id}, {"token", ticket.token}, {"status_url", where}, {"design", s.designs->describe(ticket.id)}});
}

}  // namespace

std::shared_ptr<const GalleryEntry> ServerState::find_scene(const std::string& id, bool* loading) const {
  *loading = false;
  if (const auto it = gallery->entries.find(id); it != gallery->entries.end()) return it->second;
  if (!designs) return nullptr;
  auto found = designs->scene(id);
  *loading = found.loading;
  return found.entry;
}

bool route_designs(ServerState& s, SoupServerMessage* msg, const std::string& path) {
  static const std::regex design_path("^/api/v1/designs/([0-9a-f]{32})$");
  const std::string method = soup_server_message_get_method(msg);
  if (path == "/api/v1/designs") {
    // No listing: a design is seen by those who hold its id.
    if (method != "POST") not_allowed(s, msg, "POST");
    else upload(s, msg);
    return true;
  }
  std::smatch m;
  if (path.rfind("/api/v1/designs/", 0) != 0) return false;
  const nlohmann::json state = std::regex_match(path, m, design_path) && s.designs ? s.designs->describe(m[1]) : nullptr;
  if (method == "GET" || method == "HEAD") {
    if (state.is_null()) reply_problem(msg, s.metrics, SOUP_STATUS_NOT_FOUND, "no such design");
    else reply_json(msg, SOUP_STATUS_OK, state);
  } else if (method == "DELETE") {
    // One answer for an unknown id and a wrong token, as for sessions.
    if (state.is_null() || !s.designs->remove(m[1], bearer_token(msg))) {
      soup_message_headers_replace(soup_server_message_get_response_headers(msg), "WWW-Authenticate", "Bearer");
      reply_problem(msg, s.metrics, SOUP_STATUS_UNAUTHORIZED, "no design with this id and token");
    } else {
      soup_server_message_set_status(msg, SOUP_STATUS_NO_CONTENT, nullptr);
    }
  } else {
    not_allowed(s, msg, "GET, HEAD, DELETE");
  }
  return true;
}

}  // namespace caustic::server
