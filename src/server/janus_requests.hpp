// SPDX-License-Identifier: LGPL-2.1-or-later
// What causticd says to Janus's streaming plugin and reads from it (its
// admin API, janus_admin.hpp): a mountpoint's create and destroy requests,
// the ports a create gives, and the token a viewer shows Janus.
#pragma once

#include "broadcast.hpp"
#include "caustic/server/config.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace caustic::server {

/// The create request of mountpoint `m` for session `session_id`, streaming
/// `codec` ("h264" or "vp8") as the server is configured. Ports 0 let Janus
/// choose (first time); a re-creation after a Janus restart asks for the
/// same ones.
nlohmann::json create_request(const Mountpoint& m, const std::string& session_id, const std::string& codec,
                              const ServerConfig& c);

/// The destroy request of `m`: its id and secret.
nlohmann::json destroy_request(const Mountpoint& m);

/// The RTP and data ports in Janus's answer to a create (`response`) into
/// `m`; false unless both are there and RTCP sits on the port after RTP
/// (what rtpsink sends to and listens on). Fields of other types: false.
bool read_ports(const nlohmann::json& response, Mountpoint& m);

/// Janus's token_auth token for the streaming plugin, valid until
/// `expires` (Unix seconds): "<expires>,janus,janus.plugin.streaming:" and
/// the Base64 HMAC-SHA1 of what precedes the colon, keyed with `secret`.
std::string janus_token(const std::string& secret, std::int64_t expires);

}  // namespace caustic::server
