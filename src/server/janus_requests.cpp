// SPDX-License-Identifier: LGPL-2.1-or-later
#include "janus_requests.hpp"

#include "h264_level.hpp"

#include <glib.h>

namespace caustic::server {

nlohmann::json create_request(const Mountpoint& m, const std::string& session_id, const std::string& codec,
                              const ServerConfig& c) {
  nlohmann::json video = {{"type", "video"}, {"mid", "v"},          {"label", "caustic"},
                          {"port", m.video_port}, {"rtcpport", m.video_port ? m.video_port + 1 : 0},
                          {"iface", c.janus_rtp_address}, {"bufferkf", true}};
  if (codec == "h264") {
    // Chrome answers packetization-mode=0 to an offer without it.
    video["pt"] = 102;
    video["codec"] = "h264";
    video["fmtp"] = "profile-level-id=" + profile_level_id(h264_level(c.width, c.height, c.framerate, c.bitrate_kbps)) +
                    ";packetization-mode=1";
  } else {
    video["pt"] = 96;
    video["codec"] = "vp8";
  }
  const nlohmann::json data = {{"type", "data"}, {"mid", "d"}, {"label", "frames"}, {"datatype", "text"},
                               {"port", m.data_port}, {"iface", c.janus_rtp_address}};
  return {{"request", "create"}, {"type", "rtp"},     {"id", m.id},       {"name", "causticd-" + session_id},
          {"is_private", true},  {"secret", m.secret}, {"pin", m.pin},     {"permanent", false},
          {"media", {video, data}}};
}

nlohmann::json destroy_request(const Mountpoint& m) {
  return {{"request", "destroy"}, {"id", m.id}, {"secret", m.secret}};
}

// Any field of another type (a Janus of another version, or something else
// on its port) makes the ports unusable, never an exception in the
// library's callback.
bool read_ports(const nlohmann::json& response, Mountpoint& m) {
  const auto field = [](const nlohmann::json& object, const char* key) -> const nlohmann::json* {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  };
  const auto port_of = [&](const nlohmann::json& p, const char* key) {
    const nlohmann::json* v = field(p, key);
    return v && v->is_number_unsigned() && v->get<std::uint64_t>() <= 65535 ? static_cast<int>(v->get<std::uint64_t>()) : 0;
  };
  const nlohmann::json* stream = field(response, "stream");
  const nlohmann::json* ports = stream ? field(*stream, "ports") : nullptr;
  if (!ports || !ports->is_array()) return false;
  for (const auto& p : *ports) {
    const nlohmann::json* type = field(p, "type");
    if (!type || !type->is_string()) continue;
    if (*type == "video") {
      m.video_port = port_of(p, "port");
      if (port_of(p, "rtcp_port") != m.video_port + 1) return false;
    } else if (*type == "data") {
      m.data_port = port_of(p, "port");
    }
  }
  return m.video_port > 0 && m.data_port > 0;
}

std::string janus_token(const std::string& secret, std::int64_t expires) {
  const std::string data = std::to_string(expires) + ",janus,janus.plugin.streaming";
  GHmac* hmac = g_hmac_new(G_CHECKSUM_SHA1, reinterpret_cast<const guchar*>(secret.data()), secret.size());
  g_hmac_update(hmac, reinterpret_cast<const guchar*>(data.data()), static_cast<gssize>(data.size()));
  guint8 digest[20];
  gsize size = sizeof digest;
  g_hmac_get_digest(hmac, digest, &size);
  g_hmac_unref(hmac);
  gchar* base64 = g_base64_encode(digest, size);
  const std::string token = data + ":" + base64;
  g_free(base64);
  return token;
}

}  // namespace caustic::server
