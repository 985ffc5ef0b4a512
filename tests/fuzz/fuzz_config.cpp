// SPDX-License-Identifier: LGPL-2.1-or-later
// load_config_file on any file: a ConfigError leaves the configuration as
// it was; a file that is taken yields settings inside the documented ranges
// (docs/configuration.md), whatever the text looked like.
#include "caustic/server/config.hpp"
#include "fuzz_support.hpp"

#include <cstdint>
#include <cstring>
#include <tuple>

namespace {

auto fields(const caustic::server::ServerConfig& c) {
  return std::tie(c.bind_address, c.port, c.max_sessions, c.codec, c.bitrate_kbps, c.framerate, c.width, c.height,
                  c.keyframe_interval, c.stun_server, c.turn_server, c.ice_addresses, c.idle_timeout_s,
                  c.max_body_bytes, c.scenes_dir, c.web_dir, c.log_level, c.egl_device, c.stall_timeout_s,
                  c.settle_ms, c.max_connections, c.max_connections_per_address, c.header_timeout_s,
                  c.body_timeout_s, c.connection_idle_timeout_s, c.max_ws_message_bytes, c.rate_limit_per_s,
                  c.rate_limit_burst, c.max_sessions_per_address, c.viewer_timeout_s, c.session_create_token);
}

bool in(long long v, long long lo, long long hi) { return v >= lo && v <= hi; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using caustic::server::ServerConfig;
  caustic::fuzz::MemFile file(data, size);
  ServerConfig config;
  const ServerConfig before = config;
  try {
    caustic::server::load_config_file(config, file.path());
  } catch (const caustic::server::ConfigError& e) {
    FUZZ_CHECK(std::strlen(e.what()) > 0);
    FUZZ_CHECK(fields(config) == fields(before));
    return 0;
  }
  const ServerConfig& c = config;
  FUZZ_CHECK(in(c.port, 0, 65535));
  FUZZ_CHECK(in(c.max_sessions, 1, 1000));
  FUZZ_CHECK(c.codec == "vp8" || c.codec == "h264");
  FUZZ_CHECK(in(c.bitrate_kbps, 100, 100000));
  FUZZ_CHECK(in(c.framerate, 1, 120));
  FUZZ_CHECK(in(c.width, 16, 4096) && c.width % 8 == 0);
  FUZZ_CHECK(in(c.height, 16, 4096) && c.height % 2 == 0);
  FUZZ_CHECK(in(c.keyframe_interval, 1, 10000));
  FUZZ_CHECK(in(c.idle_timeout_s, 1, 86400));
  FUZZ_CHECK(in(static_cast<long long>(c.max_body_bytes), 1024, 16 * 1024 * 1024));
  FUZZ_CHECK(c.log_level == "error" || c.log_level == "warning" || c.log_level == "notice" || c.log_level == "info" ||
             c.log_level == "debug");
  FUZZ_CHECK(in(c.egl_device, -1, 63));
  FUZZ_CHECK(in(c.stall_timeout_s, 2, 3600));
  FUZZ_CHECK(in(c.settle_ms, 0, 10000));
  FUZZ_CHECK(in(c.max_connections, 8, 100000));
  FUZZ_CHECK(in(c.max_connections_per_address, 1, 100000));
  FUZZ_CHECK(in(c.header_timeout_s, 1, 600));
  FUZZ_CHECK(in(c.body_timeout_s, 1, 3600));
  FUZZ_CHECK(in(c.connection_idle_timeout_s, 1, 3600));
  FUZZ_CHECK(in(static_cast<long long>(c.max_ws_message_bytes), 4096, 16 * 1024 * 1024));
  FUZZ_CHECK(in(c.rate_limit_per_s, 1, 100000));
  FUZZ_CHECK(in(c.rate_limit_burst, 1, 100000));
  FUZZ_CHECK(in(c.max_sessions_per_address, 1, 1000));
  FUZZ_CHECK(in(c.viewer_timeout_s, 2, 3600));
  // A bearer token goes into comparisons and headers: no spaces, no controls.
  FUZZ_CHECK(c.session_create_token.empty() ||
             (in(static_cast<long long>(c.session_create_token.size()), 16, 256) &&
              c.session_create_token.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                       "0123456789._~+/=-") == std::string::npos));
  FUZZ_CHECK(!c.bind_address.empty());
  for (const auto& a : c.ice_addresses) FUZZ_CHECK(!a.empty() && a.find(',') == std::string::npos);
  return 0;
}
