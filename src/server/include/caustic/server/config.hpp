// SPDX-License-Identifier: LGPL-2.1-or-later
// Settings of `causticd serve`: a config file of `key = value` lines,
// overridden by CAUSTICD_* environment variables, overridden by flags.
// docs/configuration.md lists every key.
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustic::server {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ServerConfig {
  std::string bind_address = "127.0.0.1";
  int port = 8080;
  int max_sessions = 12;                  ///< measured: still sessions a 2-core host holds (docs/scaling.md)
  // Several instances behind a proxy (docs/scaling.md).
  int instance_index = 0;                 ///< this instance's number in session URLs (/i/<n>/...); 0: none
  int drain_timeout_s = 60;               ///< on SIGTERM, running sessions may go on this long; 0: stop at once
  int agent_port = 0;                     ///< TCP port of the capacity agent (HAProxy agent-check); 0: off
  std::string ice_port_range;             ///< "lo-hi": UDP ports ICE may use; empty: any
  std::vector<std::string> trusted_proxies;  ///< peers whose X-Forwarded-For names the client
  // Broadcast sessions through the Janus WebRTC server (docs/scaling.md).
  std::string janus_admin_url;            ///< http://127.0.0.1:7088/admin; empty: no broadcasts
  std::string janus_admin_secret;         ///< Janus's admin_secret
  std::string janus_streaming_key;        ///< the streaming plugin's admin_key
  std::string janus_token_secret;         ///< Janus's token_auth_secret: viewer tokens are signed with it
  std::string janus_ws_url;               ///< where viewers' browsers reach Janus's WebSocket API
  std::string janus_rtp_address = "127.0.0.1";  ///< Janus's RTP listener, as seen from here
  int viewer_link_ttl_s = 3600;           ///< a viewer link's token expires this long after it was made
  int broadcast_timeout_s = 3600;         ///< a broadcast whose presenter sends nothing this long ends
  std::string codec = "vp8";              ///< default when a session names none
  int bitrate_kbps = 4000;
  int framerate = 30;
  int width = 1024;
  int height = 1024;
  int keyframe_interval = 60;             ///< frames between unrequested key frames
  std::string stun_server;                ///< stun://host:port, empty: none
  std::string turn_server;                ///< turn(s)://user:password@host:port, empty: none
  std::vector<std::string> ice_addresses; ///< local addresses ICE may use; empty: every interface
  int idle_timeout_s = 60;                ///< reclaim a session with no peer for this long
  std::size_t max_body_bytes = 64 * 1024;
  std::filesystem::path scenes_dir;       ///< empty: <data>/assets/scenes
  std::filesystem::path web_dir;          ///< empty: <data>/web
  std::string log_level = "info";         ///< error, warning, notice, info or debug
  int egl_device = -1;                    ///< index of the hardware EGL device; -1: the first usable
  int stall_timeout_s = 20;               ///< a render thread stuck this long stops the watchdog pings
  int still_interval_ms = 1000;           ///< an unchanged picture is re-sent this often; 0: every frame
  int settle_ms = 40;                     ///< still this long -> the full frame after previews; 0: no previews
  // Limits on what clients may hold or send (docs/reliability.md says why
  // each default is where it is).
  int max_connections = 512;              ///< open client connections in total; 503 beyond
  int max_connections_per_address = 64;   ///< open connections from one client address; 503 beyond
  int header_timeout_s = 10;              ///< a request head must arrive within this
  int body_timeout_s = 30;                ///< from the head to the answer sent
  int connection_idle_timeout_s = 10;     ///< no byte moving on a plain HTTP connection this long
  std::size_t max_ws_message_bytes = 64 * 1024;  ///< a signalling message, all its fragments
  int rate_limit_per_s = 60;              ///< mutating requests per client address and second
  int rate_limit_burst = 120;             ///< ... and how many may come at once
  int max_sessions_per_address = 2;       ///< sessions one client address may hold
  int viewer_timeout_s = 30;              ///< a connected viewer silent this long loses its session
  std::string session_create_token;       ///< when set, creating a session needs it as a bearer token
  // Visitors' pictures made into glass (docs/design.md, "Over the API").
  bool design_uploads = true;             ///< POST /api/v1/designs accepts pictures
  std::string design_upload_token;        ///< when set, uploading needs it as a bearer token
  int design_max_upload_bytes = 8 * 1024 * 1024;  ///< a picture's bytes; 413 beyond, before the body is read
  int design_max_pixels = 4096 * 4096;    ///< a picture's width x height by its header; 413 beyond
  int design_queue = 4;                   ///< designs waiting or running; 503 beyond
  int design_workers = 1;                 ///< designs running at once
  int design_resolution = 512;            ///< design grid cells per side
  int design_uploads_per_hour = 20;       ///< per client address; 429 beyond
  int design_expiry_s = 7 * 24 * 3600;    ///< a design is removed this long after its upload unless kept
  int design_max_stored = 100;            ///< designs kept at once (any state); 503 beyond
  std::filesystem::path state_dir;        ///< empty: $STATE_DIRECTORY, else $XDG_STATE_HOME/causticd, else ~/.local/state/causticd

  /// What reading the settings found worth saying (a key set in one place
  /// and overridden in a later one): logged at start and at every reload.
  std::vector<std::string> warnings;

  bool operator==(const ServerConfig&) const = default;
};

/// Where each key was set while the layers are read (file, environment,
/// flags), so that a value an operator chose and a later layer replaces is
/// said rather than silently dropped. A value equal to the default (as the
/// shipped file writes every key) is no choice: replacing it is not said.
class ConfigSources {
 public:
  /// Records that `key` was just set to `value` at `where` ("FILE:LINE",
  /// "environment CAUSTICD_PORT", "--port"); adds a warning to `config`
  /// when an earlier place chose another, non-default value.
  void set(ServerConfig& config, const std::string& key, const std::string& value, const std::string& where);

 private:
  struct Origin {
    std::string value, where;
  };
  std::map<std::string, Origin> origins_;
};

/// The gallery folder: scenes_dir, or <data>/assets/scenes when empty.
std::filesystem::path scenes_folder(const ServerConfig& config, const std::filesystem::path& data_dir);
/// The folder served as static files: web_dir, or <data>/web when empty.
std::filesystem::path web_folder(const ServerConfig& config, const std::filesystem::path& data_dir);

/// Where designs are kept: state_dir, or the first of $STATE_DIRECTORY (set
/// by systemd's StateDirectory=), $XDG_STATE_HOME/causticd and
/// $HOME/.local/state/causticd.
std::filesystem::path state_folder(const ServerConfig& config);

/// With janus_admin_url set, every key broadcasts need is set too. Throws
/// ConfigError naming the first that is not.
void check_broadcast_keys(const ServerConfig& config);
/// Checks what a file alone cannot: the folders exist, the default codec's
/// pipeline is among the data files, and check_broadcast_keys. Throws
/// ConfigError naming the key.
void check_config(const ServerConfig& config, const std::filesystem::path& data_dir);

/// Sets one key from text, checking type and range. Throws ConfigError that
/// names the key.
void set_config_value(ServerConfig& config, const std::string& key, const std::string& value);

/// The longest value a key takes (after trimming): more than any address
/// list or path needs.
inline constexpr std::size_t kMaxConfigValueBytes = 4096;

/// Reads `key = value` lines ('#' starts a comment). Throws ConfigError with
/// the file, line and key on any error; `config` is untouched then.
void load_config_file(ServerConfig& config, const std::filesystem::path& file, ConfigSources* sources = nullptr);

/// Applies CAUSTICD_<KEY> variables (e.g. CAUSTICD_PORT=9000) from `environ`.
void load_config_environment(ServerConfig& config, ConfigSources* sources = nullptr);
/// The same from `entries` ("NAME=VALUE"): a server reads its environment
/// once, at the start (config_environment()), since no one can change it
/// from outside and a reload would otherwise read what the server itself set.
void load_config_environment(ServerConfig& config, ConfigSources* sources, const std::vector<std::string>& entries);
/// This process's CAUSTICD_ variables now, as "NAME=VALUE".
std::vector<std::string> config_environment();

/// The keys, for documentation and help text.
const std::vector<std::string>& config_keys();

}  // namespace caustic::server
