// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/server/config.hpp"

#include "ascii.hpp"
#include "local_addresses.hpp"
#include "caustic/json_text.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <regex>
#include <sstream>

#include <arpa/inet.h>
#include <unistd.h>  // environ

namespace caustic::server {
namespace {

// ", got "value"" for an error, the value quoted safely and at most 64 bytes of it.
std::string got(const std::string& value) {
  return value.empty() ? ", got an empty value" : ", got \"" + printable_name(value) + "\"";
}

int parse_int(const std::string& key, const std::string& text, int lo, int hi) {
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < lo || value > hi)
    throw ConfigError(key + ": must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" + got(text));
  return value;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// A host as RFC 3986 writes it (a name or IPv4 address, or an IPv6
// address in brackets), then an optional port: groups host, ":port", port.
constexpr const char* kHostPort = "([A-Za-z0-9.-]+|\\[[0-9A-Fa-f:.]+\\])(:([0-9]{1,5}))?";

// A port a URL names, when it names one, is 1 to 65535: five digits alone
// let 99999 through to a STUN, TURN or Janus address nothing listens on.
void check_port(const std::string& key, const std::string& value, const std::ssub_match& port) {
  if (port.matched && (std::stoi(port.str()) < 1 || std::stoi(port.str()) > 65535))
    throw ConfigError(key + ": the port must be 1 to 65535" + got(value));
}

// A user and password are RFC 3986 userinfo: any other byte percent-encoded
// (a '#' or '?' ended the URI that webrtcbin parses, which then left TURN
// off without a word; a quote would end the pipeline's text).
void check_uri(const std::string& key, const std::string& value, const char* schemes) {
  const std::regex pattern(std::string("^(") + schemes + ")://([A-Za-z0-9._~%!$&()*+,;=:-]+@)?" + kHostPort + "$");
  std::smatch m;
  if (value.empty()) return;
  if (std::regex_match(value, m, pattern)) return check_port(key, value, m[5]);
  const std::regex userinfo(std::string("^(") + schemes + ")://[^\\s/]*@" + kHostPort + "$");
  if (std::regex_match(value, userinfo))
    throw ConfigError(key + ": write a '#', '?', '@', '/', quote or space in the user or password as %XX (%23 for #)");
  throw ConfigError(key + ": must look like " + std::string(schemes) + "://host:port" + got(value));
}

// A numeric IPv4 or IPv6 address, each part in range (999.1.1.1 is not one).
bool ip_address(const std::string& text) {
  unsigned char bytes[16];
  return inet_pton(AF_INET, text.c_str(), bytes) == 1 || inet_pton(AF_INET6, text.c_str(), bytes) == 1;
}

// Whether a numeric address names one host: not "any" (0.0.0.0, ::),
// multicast or the IPv4 broadcast address, which a listening socket may
// take but a candidate, a peer or a destination may not.
bool one_host(const std::string& text) {
  const auto one_v4 = [](const unsigned char* b) {
    return !(b[0] == 0 && b[1] == 0 && b[2] == 0 && b[3] == 0) && (b[0] & 0xF0) != 0xE0 &&
           !(b[0] == 255 && b[1] == 255 && b[2] == 255 && b[3] == 255);
  };
  unsigned char b[16] = {};
  if (inet_pton(AF_INET, text.c_str(), b) == 1) return one_v4(b);
  if (inet_pton(AF_INET6, text.c_str(), b) != 1) return false;
  // ::ffff:a.b.c.d is the IPv4 address a.b.c.d.
  const bool mapped = std::all_of(b, b + 10, [](unsigned char c) { return c == 0; }) && b[10] == 0xFF && b[11] == 0xFF;
  if (mapped) return one_v4(b + 12);
  return !std::all_of(b, b + 16, [](unsigned char c) { return c == 0; }) && b[0] != 0xFF;
}

// A comma-separated list of IP addresses, each of one host; empty items
// are skipped.
std::vector<std::string> address_list(const std::string& key, const std::string& value) {
  std::vector<std::string> list;
  for (std::size_t start = 0; start <= value.size();) {
    const auto comma = std::min(value.find(',', start), value.size());
    const std::string item = trim(value.substr(start, comma - start));
    if (!item.empty()) {
      if (!ip_address(item)) throw ConfigError(key + ": \"" + printable_name(item) + "\" is not an IP address");
      if (!one_host(item))
        throw ConfigError(key + ": \"" + item + "\" names no one host (an any, multicast or broadcast address)");
      list.push_back(item);
    }
    start = comma + 1;
  }
  return list;
}

}  // namespace

namespace {

// Integer keys with nothing to check beyond their range: one table that
// set_config_value and config_keys both read.
struct IntKey {
  const char* name;
  int ServerConfig::*field;
  int lo, hi;
};
constexpr IntKey kIntKeys[] = {
    {"port", &ServerConfig::port, 0, 65535},
    {"max_sessions", &ServerConfig::max_sessions, 1, 1000},
    {"instance_index", &ServerConfig::instance_index, 0, 999},
    {"drain_timeout_s", &ServerConfig::drain_timeout_s, 0, 86400},
    {"agent_port", &ServerConfig::agent_port, 0, 65535},
    {"viewer_link_ttl_s", &ServerConfig::viewer_link_ttl_s, 10, 7 * 24 * 3600},
    {"broadcast_timeout_s", &ServerConfig::broadcast_timeout_s, 10, 7 * 24 * 3600},
    {"bitrate_kbps", &ServerConfig::bitrate_kbps, 100, 100000},
    {"framerate", &ServerConfig::framerate, 1, 120},
    {"keyframe_interval", &ServerConfig::keyframe_interval, 1, 10000},
    {"idle_timeout_s", &ServerConfig::idle_timeout_s, 1, 86400},
    {"egl_device", &ServerConfig::egl_device, -1, 63},
    {"stall_timeout_s", &ServerConfig::stall_timeout_s, 2, 3600},
    {"settle_ms", &ServerConfig::settle_ms, 0, 10000},
    {"still_interval_ms", &ServerConfig::still_interval_ms, 0, 60000},
    {"max_connections", &ServerConfig::max_connections, 8, 100000},
    {"max_connections_per_address", &ServerConfig::max_connections_per_address, 1, 100000},
    {"header_timeout_s", &ServerConfig::header_timeout_s, 1, 600},
    {"body_timeout_s", &ServerConfig::body_timeout_s, 1, 3600},
    {"connection_idle_timeout_s", &ServerConfig::connection_idle_timeout_s, 1, 3600},
    {"rate_limit_per_s", &ServerConfig::rate_limit_per_s, 1, 100000},
    {"rate_limit_burst", &ServerConfig::rate_limit_burst, 1, 100000},
    {"max_sessions_per_address", &ServerConfig::max_sessions_per_address, 1, 1000},
    {"viewer_timeout_s", &ServerConfig::viewer_timeout_s, 2, 3600},
    {"design_max_upload_bytes", &ServerConfig::design_max_upload_bytes, 1024, 64 * 1024 * 1024},
    {"design_max_pixels", &ServerConfig::design_max_pixels, 64 * 64, 1 << 26},
    {"design_queue", &ServerConfig::design_queue, 1, 1000},
    {"design_workers", &ServerConfig::design_workers, 1, 16},
    {"design_resolution", &ServerConfig::design_resolution, 64, 1024},
    {"design_uploads_per_hour", &ServerConfig::design_uploads_per_hour, 1, 100000},
    {"design_expiry_s", &ServerConfig::design_expiry_s, 1, 10 * 365 * 24 * 3600},
    {"design_max_stored", &ServerConfig::design_max_stored, 1, 100000},
};

// Keys whose values need more than a range; set_config_value handles each.
constexpr const char* kOtherKeys[] = {"bind_address", "codec",         "width",          "height",
                                      "stun_server",  "turn_server",   "ice_addresses",  "max_body_bytes",
                                      "scenes_dir",   "web_dir",       "log_level",      "max_ws_message_bytes",
                                      "session_create_token", "design_uploads", "design_upload_token", "state_dir",
                                      "ice_port_range", "trusted_proxies", "janus_admin_url", "janus_admin_secret",
                                      "janus_streaming_key", "janus_token_secret", "janus_ws_url", "janus_rtp_address"};

}  // namespace

const std::vector<std::string>& config_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> out(std::begin(kOtherKeys), std::end(kOtherKeys));
    for (const auto& k : kIntKeys) out.push_back(k.name);
    return out;
  }();
  return keys;
}

void set_config_value(ServerConfig& c, const std::string& key, const std::string& raw) {
  const std::string value = trim(raw);
  // Far beyond any address list or path; the patterns below are matched by
  // recursion, which a value of some 30,000 characters took off the stack.
  if (value.size() > kMaxConfigValueBytes)
    throw ConfigError(printable_name(key) + ": a value is at most " + std::to_string(kMaxConfigValueBytes) +
                      " characters, got " + std::to_string(value.size()));
  for (const auto& k : kIntKeys)
    if (key == k.name) {
      c.*k.field = parse_int(key, value, k.lo, k.hi);
      return;
    }
  if (key == "bind_address") {
    if (value != "localhost" && !ip_address(value))
      throw ConfigError(key + ": must be an IP address" + got(value));
    c.bind_address = value;
  } else if (key == "codec") {
    if (value != "vp8" && value != "h264") throw ConfigError(key + ": must be vp8 or h264" + got(value));
    c.codec = value;
  } else if (key == "width") {
    // The GPU writes I420 planes packed: widths in steps of 8, even heights.
    c.width = parse_int(key, value, 16, 4096);
    if (c.width % 8) throw ConfigError(key + ": must be a multiple of 8, got " + value);
  } else if (key == "height") {
    c.height = parse_int(key, value, 16, 4096);
    if (c.height % 2) throw ConfigError(key + ": must be even, got " + value);
  } else if (key == "stun_server") {
    check_uri(key, value, "stun");
    c.stun_server = value;
  } else if (key == "turn_server") {
    check_uri(key, value, "turn|turns");
    c.turn_server = value;
  } else if (key == "ice_addresses") {
    c.ice_addresses = address_list(key, value);
    for (const auto& a : c.ice_addresses)
      if (!host_has_address(a)) c.warnings.push_back(key + ": " + a + " is on none of this host's interfaces: ICE offers nothing there");
  } else if (key == "trusted_proxies") {
    c.trusted_proxies = address_list(key, value);
  } else if (key == "janus_admin_url") {
    // Janus's admin API can do anything to it: it stays on this host.
    static const std::regex admin("^http://(127\\.0\\.0\\.1|localhost|\\[::1\\]):([0-9]{1,5})(/[A-Za-z0-9._~/-]*)?$");
    std::smatch m;
    if (!value.empty() && !std::regex_match(value, m, admin))
      throw ConfigError(key + ": must be http://127.0.0.1:PORT/PATH (the admin API stays on this host)" + got(value));
    if (!value.empty()) check_port(key, value, m[2]);
    c.janus_admin_url = value;
  } else if (key == "janus_admin_secret" || key == "janus_streaming_key" || key == "janus_token_secret") {
    static const std::regex secret("^[A-Za-z0-9._~+/=-]{16,256}$");
    if (!value.empty() && !std::regex_match(value, secret))
      throw ConfigError(key + ": must be 16 to 256 characters of A-Z a-z 0-9 . _ ~ + / = -");
    (key == "janus_admin_secret" ? c.janus_admin_secret
                                 : key == "janus_streaming_key" ? c.janus_streaming_key : c.janus_token_secret) = value;
  } else if (key == "janus_ws_url") {
    static const std::regex ws(std::string("^(wss?://") + kHostPort + ")?/[A-Za-z0-9._~/-]*$");
    std::smatch m;
    if (!value.empty() && !std::regex_match(value, m, ws))
      throw ConfigError(key + ": must be ws://host:port/path, wss://host/path or a path on this server" + got(value));
    if (!value.empty()) check_port(key, value, m[4]);
    c.janus_ws_url = value;
  } else if (key == "janus_rtp_address") {
    const auto list = address_list(key, value);
    if (list.size() != 1) throw ConfigError(key + ": must be one IP address" + got(value));
    c.janus_rtp_address = list[0];
  } else if (key == "ice_port_range") {
    static const std::regex range("^([0-9]{1,5})-([0-9]{1,5})$");
    std::smatch m;
    if (!value.empty() && (!std::regex_match(value, m, range) || std::stoi(m[1]) < 1024 || std::stoi(m[2]) > 65535 ||
                           std::stoi(m[1]) > std::stoi(m[2])))
      throw ConfigError(key + ": must be lo-hi with 1024 <= lo <= hi <= 65535" + got(value));
    c.ice_port_range = value;
  } else if (key == "max_body_bytes") {
    c.max_body_bytes = static_cast<std::size_t>(parse_int(key, value, 1024, 16 * 1024 * 1024));
  } else if (key == "max_ws_message_bytes") {
    c.max_ws_message_bytes = static_cast<std::size_t>(parse_int(key, value, 4096, 16 * 1024 * 1024));
  } else if (key == "scenes_dir") {
    c.scenes_dir = value;
  } else if (key == "web_dir") {
    c.web_dir = value;
  } else if (key == "log_level") {
    static const std::regex level("^(error|warning|notice|info|debug)$");
    if (!std::regex_match(value, level))
      throw ConfigError(key + ": must be error, warning, notice, info or debug" + got(value));
    c.log_level = value;
  } else if (key == "session_create_token" || key == "design_upload_token") {
    static const std::regex token("^[A-Za-z0-9._~+/=-]{16,256}$");
    if (!value.empty() && !std::regex_match(value, token))
      throw ConfigError(key + ": must be 16 to 256 characters of A-Z a-z 0-9 . _ ~ + / = -");
    (key == "session_create_token" ? c.session_create_token : c.design_upload_token) = value;
  } else if (key == "design_uploads") {
    if (value != "on" && value != "off") throw ConfigError(key + ": must be on or off" + got(value));
    c.design_uploads = value == "on";
  } else if (key == "state_dir") {
    c.state_dir = value;
  } else {
    throw ConfigError(printable_name(key) + ": unknown key");
  }
}

void ConfigSources::set(ServerConfig& config, const std::string& key, const std::string& value,
                        const std::string& where) {
  auto [it, first] = origins_.try_emplace(key, Origin{value, where});
  if (first) return;
  // Compared as settings, not text ("60" and " 60" are one value).
  ServerConfig earlier, now;
  set_config_value(earlier, key, it->second.value);
  set_config_value(now, key, value);
  // A default written out (the shipped file writes every key) may be
  // replaced from a later place unsaid; a key written twice in one file is a
  // slip whatever its first value.
  const auto place = [](const std::string& w) { return w.substr(0, w.rfind(':')); };
  if (earlier != now && (earlier != ServerConfig{} || place(it->second.where) == place(where)))
    config.warnings.push_back(key + ": the value set at " + it->second.where + " is overridden by " + where);
  it->second = Origin{value, where};
}

void load_config_file(ServerConfig& config, const std::filesystem::path& file, ConfigSources* sources) {
  // Read whole but bounded: a config is a few hundred bytes, and a device
  // or a runaway file must not take the memory.
  constexpr std::size_t kMaxBytes = 1 << 20;
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) throw ConfigError("config file " + file.string() + " is a folder");
  // Opened without waiting: a pipe or socket waits for a writer that may
  // never come, a device (a terminal) or a kernel file such as /proc/kmsg
  // for input that may never come.
  FileText read = read_file_text(file, kMaxBytes);
  if (read.not_a_file) throw ConfigError("config file " + file.string() + " is a pipe, socket, device or kernel file, not a file");
  if (!read.opened) throw ConfigError("cannot read config file " + file.string() + why_unread(read));
  if (read.too_large) throw ConfigError("config file " + file.string() + " is larger than 1 MiB");
  std::string text = std::move(read.text);
  // Some editors start a UTF-8 file with a byte-order mark: no part of the first key.
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  std::istringstream in(text);
  ServerConfig next = config;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    // A comment starts with '#' at the line's start or after a blank: a '#'
    // inside a value (a TURN password, a URL's fragment) is the value's.
    std::size_t hash = line.find('#');
    while (hash != std::string::npos && hash > 0 && line[hash - 1] != ' ' && line[hash - 1] != '\t')
      hash = line.find('#', hash + 1);
    const std::string text = trim(line.substr(0, hash));
    if (text.empty()) continue;
    const auto eq = text.find('=');
    const std::string where = file.string() + ":" + std::to_string(number) + ": ";
    if (eq == std::string::npos) throw ConfigError(where + "expected key = value");
    try {
      const std::string key = trim(text.substr(0, eq));
      set_config_value(next, key, text.substr(eq + 1));
      if (sources) sources->set(next, key, text.substr(eq + 1), where.substr(0, where.size() - 2));
    } catch (const ConfigError& e) {
      throw ConfigError(where + e.what());
    }
  }
  config = next;
}

std::filesystem::path scenes_folder(const ServerConfig& c, const std::filesystem::path& data_dir) {
  return c.scenes_dir.empty() ? data_dir / "assets" / "scenes" : c.scenes_dir;
}

std::filesystem::path web_folder(const ServerConfig& c, const std::filesystem::path& data_dir) {
  return c.web_dir.empty() ? data_dir / "web" : c.web_dir;
}

std::filesystem::path state_folder(const ServerConfig& c) {
  if (!c.state_dir.empty()) return c.state_dir;
  // systemd may list several folders, colon-separated: the first is ours.
  if (const char* dir = std::getenv("STATE_DIRECTORY"); dir && *dir) {
    const std::string first = std::string(dir).substr(0, std::string(dir).find(':'));
    if (!first.empty()) return first;
  }
  if (const char* xdg = std::getenv("XDG_STATE_HOME"); xdg && *xdg == '/') return std::filesystem::path(xdg) / "causticd";
  if (const char* home = std::getenv("HOME"); home && *home == '/')
    return std::filesystem::path(home) / ".local" / "state" / "causticd";
  return "/var/lib/causticd";
}

void check_config(const ServerConfig& c, const std::filesystem::path& data_dir) {
  const auto scenes = scenes_folder(c, data_dir);
  const auto web = web_folder(c, data_dir);
  // The error_code forms: a name too long for the system is "not a folder"
  // too, not a filesystem_error that quotes it whole.
  std::error_code ec;
  if (!std::filesystem::is_directory(scenes, ec))
    throw ConfigError("scenes_dir: " + printable_name(scenes.string(), 256) + " is not a folder");
  if (!std::filesystem::is_directory(web, ec))
    throw ConfigError("web_dir: " + printable_name(web.string(), 256) + " is not a folder");
  if (!std::filesystem::is_regular_file(data_dir / "pipelines" / (c.codec + ".pipeline"), ec))
    throw ConfigError("codec: no pipeline " + c.codec + ".pipeline in " + (data_dir / "pipelines").string());
  // Unwritable, it leaves uploads off (said); a file there is a mistake.
  if (!c.state_dir.empty() && std::filesystem::exists(c.state_dir, ec) && !std::filesystem::is_directory(c.state_dir, ec))
    throw ConfigError("state_dir: " + printable_name(c.state_dir.string(), 256) + " is not a folder");
  // Every file under web_dir is served: a state folder there would hand out
  // each design's record, its delete token and the figures kept from visitors.
  const auto real = [](const std::filesystem::path& p) {
    std::error_code e;
    const auto r = std::filesystem::weakly_canonical(p, e);
    return e ? p.lexically_normal() : r;
  };
  const auto state = real(state_folder(c)), served = real(web);
  if (std::mismatch(served.begin(), served.end(), state.begin(), state.end()).first == served.end())
    throw ConfigError("state_dir: " + printable_name(state.string(), 256) + " lies inside web_dir " +
                      printable_name(served.string(), 256) + ", whose files are served; keep it outside");
  check_broadcast_keys(c);
}

void check_broadcast_keys(const ServerConfig& c) {
  // Broadcasts need every Janus credential, and a place viewers reach.
  if (!c.janus_admin_url.empty())
    for (const auto& [key, value] : {std::pair{"janus_admin_secret", &c.janus_admin_secret},
                                     std::pair{"janus_streaming_key", &c.janus_streaming_key},
                                     std::pair{"janus_token_secret", &c.janus_token_secret},
                                     std::pair{"janus_ws_url", &c.janus_ws_url}})
      if (value->empty()) throw ConfigError(std::string(key) + ": must be set when janus_admin_url is");
}

std::vector<std::string> config_environment() {
  std::vector<std::string> entries;
  for (char** env = environ; env && *env; ++env)
    if (std::string_view(*env).rfind("CAUSTICD_", 0) == 0) entries.emplace_back(*env);
  return entries;
}

void load_config_environment(ServerConfig& config, ConfigSources* sources) {
  load_config_environment(config, sources, config_environment());
}

void load_config_environment(ServerConfig& config, ConfigSources* sources, const std::vector<std::string>& entries) {
  ServerConfig next = config;
  for (const std::string& entry : entries) {
    if (entry.rfind("CAUSTICD_", 0) != 0) continue;
    const auto eq = entry.find('=');
    const std::string key = ascii_lower(entry.substr(9, eq - 9));
    if (std::find(config_keys().begin(), config_keys().end(), key) == config_keys().end()) {
      // Read where they are used, not settings: anything else is a misspelling.
      static const std::string kRead[] = {"data_dir", "egl_device", "egl_platform"};
      if (std::find(std::begin(kRead), std::end(kRead), key) == std::end(kRead))
        next.warnings.push_back("environment " + printable_name(entry.substr(0, eq)) +
                                ": not a setting (CAUSTICD_ and a key of the config file), ignored");
      continue;
    }
    try {
      set_config_value(next, key, entry.substr(eq + 1));
      if (sources) sources->set(next, key, entry.substr(eq + 1), "environment " + entry.substr(0, eq));
    } catch (const ConfigError& e) {
      throw ConfigError("environment CAUSTICD_" + entry.substr(9, eq - 9) + ": " + e.what());
    }
  }
  config = next;
}

}  // namespace caustic::server
