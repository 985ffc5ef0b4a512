// SPDX-License-Identifier: LGPL-2.1-or-later
// Server configuration: file, environment and values, each bad one named.
#include "caustic/server/config.hpp"
#include "refusal.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

using namespace caustic::server;

namespace {

std::filesystem::path write_config(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

void expect_error(ServerConfig& c, const std::string& key, const std::string& value, const std::string& fragment) {
  const ServerConfig before = c;
  try {
    set_config_value(c, key, value);
    ADD_FAILURE() << key << " = " << value << " accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
  EXPECT_EQ(c.port, before.port);
  EXPECT_EQ(c.ice_addresses, before.ice_addresses);
}

}  // namespace

TEST(Config, FileSetsEveryKindOfValue) {
  ServerConfig c;
  load_config_file(c, write_config("causticd_good.conf",
                                   "# comment\nport = 9000\nbind_address=0.0.0.0\ncodec = h264  # inline comment\n"
                                   "ice_addresses = 127.0.0.1, ::1\nstun_server = stun://stun.example:3478\n"
                                   "max_sessions = 7\nlog_level = debug\negl_device = 1\nsettle_ms = 0\n"
                                   "stall_timeout_s = 5\nturn_server = turn://user:pa%23ss@turn.example:3478 #x\n\n"));
  EXPECT_EQ(c.port, 9000);
  EXPECT_EQ(c.bind_address, "0.0.0.0");
  EXPECT_EQ(c.codec, "h264");
  EXPECT_EQ(c.ice_addresses, (std::vector<std::string>{"127.0.0.1", "::1"}));
  EXPECT_EQ(c.stun_server, "stun://stun.example:3478");
  EXPECT_EQ(c.max_sessions, 7);
  EXPECT_EQ(c.log_level, "debug");
  EXPECT_EQ(c.egl_device, 1);
  EXPECT_EQ(c.settle_ms, 0);
  EXPECT_EQ(c.stall_timeout_s, 5);
  // A comment follows a blank; a TURN password's '#' is written %23.
  EXPECT_EQ(c.turn_server, "turn://user:pa%23ss@turn.example:3478");
  EXPECT_EQ(c.stun_server, "stun://stun.example:3478");
  load_config_file(c, write_config("causticd_hash.conf", "state_dir = /srv/a#b  # c\n"));  // a # not after a blank
  EXPECT_EQ(c.state_dir, "/srv/a#b");
  // A byte-order mark (some editors write one) is no part of the first key;
  // elsewhere it is no key at all.
  load_config_file(c, write_config("causticd_bom.conf", "\xEF\xBB\xBFport = 9001\n"));
  EXPECT_EQ(c.port, 9001);
  EXPECT_THROW(load_config_file(c, write_config("causticd_bom2.conf", "port = 9002\n\xEF\xBB\xBF" "codec = vp8\n")),
               ConfigError);
  EXPECT_EQ(c.port, 9001);
}

TEST(Config, TheShippedFileNamesEveryKeyAndHoldsTheDefaults) {
  ServerConfig defaults, shipped;
  load_config_file(shipped, CAUSTIC_SOURCE_DIR "/systemd/causticd.conf");
  std::ifstream in(CAUSTIC_SOURCE_DIR "/systemd/causticd.conf");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& key : config_keys()) EXPECT_NE(text.find("\n" + key + " ="), std::string::npos) << key;
  EXPECT_EQ(shipped.port, defaults.port);
  EXPECT_EQ(shipped.settle_ms, defaults.settle_ms);
  EXPECT_EQ(shipped.stall_timeout_s, defaults.stall_timeout_s);
  EXPECT_EQ(shipped.log_level, defaults.log_level);
}

TEST(Config, BadFileNamesFileLineAndKeyAndChangesNothing) {
  ServerConfig c;
  const auto file = write_config("causticd_bad.conf", "port = 9000\nframerate = fast\n");
  try {
    load_config_file(c, file);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("causticd_bad.conf:2"), std::string::npos) << what;
    EXPECT_NE(what.find("framerate"), std::string::npos) << what;
  }
  EXPECT_EQ(c.port, 8080);  // the good first line did not stick either
  EXPECT_THROW(load_config_file(c, write_config("causticd_nokey.conf", "just words\n")), ConfigError);
  EXPECT_THROW(load_config_file(c, write_config("causticd_unknown.conf", "colour = red\n")), ConfigError);
  EXPECT_THROW(load_config_file(c, "/nonexistent/causticd.conf"), ConfigError);
  // A folder is no file, and an endless one is not read to the end.
  EXPECT_THROW(load_config_file(c, std::filesystem::temp_directory_path()), ConfigError);
  const auto refusal = [&](const std::filesystem::path& file) {
    return caustic::testing::refusal<ConfigError>([&] { load_config_file(c, file); });
  };
  EXPECT_NE(refusal("/dev/zero").find("device or kernel file, not a file"), std::string::npos) << refusal("/dev/zero");
  const auto big = std::filesystem::temp_directory_path() / "causticd_big.conf";
  std::ofstream(big) << std::string((1 << 20) + 10, '#');
  EXPECT_NE(refusal(big).find("larger than 1 MiB"), std::string::npos) << refusal(big);
  std::filesystem::remove(big);
  // A pipe: opening it waited for a writer.
  const auto fifo = std::filesystem::temp_directory_path() / "causticd_fifo.conf";
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(refusal(fifo).find("is a pipe, socket, device"), std::string::npos) << refusal(fifo);
  std::filesystem::remove(fifo);
  // A kernel file says it is regular, and /proc/kmsg then waits on a read
  // (check-config held until killed) and gives away the kernel's log: none
  // is read. /proc/kmsg opens for root alone.
  EXPECT_NE(refusal("/proc/self/status").find("or kernel file, not a file"), std::string::npos)
      << refusal("/proc/self/status");
  if (::geteuid() == 0 && std::filesystem::exists("/proc/kmsg")) {
    EXPECT_NE(refusal("/proc/kmsg").find("or kernel file, not a file"), std::string::npos) << refusal("/proc/kmsg");
  }
  EXPECT_EQ(c.port, 8080);
}

TEST(Config, AValueLongerThanAnyAddressOrPathIsRefusedWithoutQuotingIt) {
  ServerConfig c;
  // 30,000 characters took the URL pattern's recursion off the stack.
  const std::string url = "stun://" + std::string(30000, 'a') + ":3478";
  expect_error(c, "stun_server", url, "stun_server: a value is at most 4096 characters, got 30012");
  try {
    set_config_value(c, "trusted_proxies", std::string(100000, '1'));
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u) << "the value was quoted whole";
  }
  try {
    set_config_value(c, "bind_address", std::string(1000, '9'));
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u) << "the value was quoted whole";
  }
  EXPECT_NO_THROW(set_config_value(c, "stun_server", "stun://" + std::string(2000, 'a') + ":3478"));
}

TEST(Config, ValuesAreCheckedAndNamed) {
  ServerConfig c;
  expect_error(c, "port", "70000", "port");
  expect_error(c, "port", "80a", "port");
  expect_error(c, "ice_port_range", "80-90", "ice_port_range");
  expect_error(c, "ice_port_range", "5000-4000", "ice_port_range");
  expect_error(c, "ice_port_range", "5000", "ice_port_range");
  expect_error(c, "instance_index", "-1", "instance_index");
  expect_error(c, "trusted_proxies", "proxy.example", "trusted_proxies");
  expect_error(c, "drain_timeout_s", "forever", "drain_timeout_s");
  expect_error(c, "max_sessions", "0", "max_sessions");
  expect_error(c, "codec", "av1", "codec");
  expect_error(c, "bind_address", "example.com; rm", "bind_address");
  expect_error(c, "bind_address", "999.1.1.1", "bind_address");  // the shape of one, not an address
  expect_error(c, "bind_address", "256.0.0.1", "bind_address");
  expect_error(c, "bind_address", "1::2::3", "bind_address");
  expect_error(c, "trusted_proxies", "10.0.0.300", "10.0.0.300");
  expect_error(c, "ice_addresses", "127.0.0.1, eth0", "eth0");
  // Addresses a socket may listen on but no candidate, peer or destination is.
  for (const char* nobody : {"0.0.0.0", "::", "224.0.0.251", "255.255.255.255", "ff02::1", "::ffff:0.0.0.0",
                             "::ffff:224.0.0.1"}) {
    expect_error(c, "ice_addresses", nobody, "names no one host");
    expect_error(c, "janus_rtp_address", nobody, "janus_rtp_address");
  }
  expect_error(c, "trusted_proxies", "10.0.0.1, ::", "names no one host");
  EXPECT_NO_THROW(set_config_value(c, "ice_addresses", "127.0.0.1, ::1, 10.1.2.3, fe80::1, ::ffff:10.0.0.1"));
  // Valid, but an address no interface of this host holds offers ICE
  // nothing: said, naming it (192.0.2.0/24 is documentation's own).
  ServerConfig fresh;
  ASSERT_NO_THROW(set_config_value(fresh, "ice_addresses", "127.0.0.1, 192.0.2.77"));
  ASSERT_EQ(fresh.warnings.size(), 1u);
  EXPECT_EQ(fresh.warnings[0], "ice_addresses: 192.0.2.77 is on none of this host's interfaces: ICE offers nothing there");
  expect_error(c, "stun_server", "http://x", "stun_server");
  expect_error(c, "stun_server", "stun://a b", "stun_server");
  expect_error(c, "turn_server", "turn://u:p@host:3478 ! filesink", "turn_server");
  // webrtcbin's URI parser ends at a '#' or '?': TURN was off without a word.
  for (const char* raw : {"turn://u:p#ss@host:3478", "turn://u:p?ss@host:3478", "turn://u:p\"ss@host:3478"})
    expect_error(c, "turn_server", raw, "as %XX (%23 for #)");
  // A URL's port is 1 to 65535, and its host a name, an IPv4 address or
  // an IPv6 one in brackets: five digits and a host of colons let these by.
  expect_error(c, "stun_server", "stun://h:99999", "stun_server: the port must be 1 to 65535");
  expect_error(c, "turn_server", "turn://u:p@h:70000", "turn_server: the port must be 1 to 65535");
  expect_error(c, "stun_server", "stun://a:b:c:d", "stun_server: must look like");
  expect_error(c, "janus_ws_url", "ws://h:99999/x", "janus_ws_url: the port must be 1 to 65535");
  expect_error(c, "janus_admin_url", "http://127.0.0.1:99999/admin", "janus_admin_url: the port must be 1 to 65535");
  expect_error(c, "janus_admin_url", "http://127.0.0.1:0/admin", "janus_admin_url: the port must be 1 to 65535");
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"stun_server", "stun://[::1]:3478"}, {"stun_server", "stun://stun.example"},
           {"turn_server", "turns://user:pw@turn.example.org:65535"}, {"janus_ws_url", "ws://[::1]:8188/janus"},
           {"janus_ws_url", "/janus"}, {"janus_admin_url", "http://[::1]:7088/admin"}})
    EXPECT_NO_THROW(set_config_value(c, key, value)) << key << " = " << value;
  expect_error(c, "width", "8", "width");
  expect_error(c, "nonsense", "1", "unknown key");
}

TEST(Config, EnvironmentOverridesAndIsChecked) {
  ServerConfig c;
  setenv("CAUSTICD_PORT", "9100", 1);
  setenv("CAUSTICD_MAX_SESSIONS", "3", 1);
  load_config_environment(c);
  EXPECT_EQ(c.port, 9100);
  EXPECT_EQ(c.max_sessions, 3);
  setenv("CAUSTICD_PORT", "-1", 1);
  try {
    load_config_environment(c);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("CAUSTICD_PORT"), std::string::npos) << e.what();
  }
  EXPECT_EQ(c.port, 9100);
  unsetenv("CAUSTICD_PORT");
  unsetenv("CAUSTICD_MAX_SESSIONS");
  // A misspelt variable is said, naming it; the ones read elsewhere are not.
  ServerConfig spelt;
  setenv("CAUSTICD_PROT", "9000", 1);
  setenv("CAUSTICD_DATA_DIR", "/usr/share/causticd", 1);
  load_config_environment(spelt);
  unsetenv("CAUSTICD_PROT");
  unsetenv("CAUSTICD_DATA_DIR");
  ASSERT_EQ(spelt.warnings.size(), 1u);
  EXPECT_NE(spelt.warnings[0].find("CAUSTICD_PROT"), std::string::npos) << spelt.warnings[0];
  EXPECT_EQ(spelt.port, 8080);
  // A server reads the environment it began with: what it set since (its
  // GL device) is not the operator's choice at a reload.
  const std::vector<std::string> began = {"CAUSTICD_PORT=9300", "PATH=/bin"};
  setenv("CAUSTICD_EGL_DEVICE", "3", 1);
  setenv("CAUSTICD_MAX_SESSIONS", "5", 1);
  ServerConfig reloaded;
  load_config_environment(reloaded, nullptr, began);
  const std::vector<std::string> now = config_environment();
  EXPECT_NE(std::find(now.begin(), now.end(), "CAUSTICD_MAX_SESSIONS=5"), now.end());
  EXPECT_EQ(std::find(now.begin(), now.end(), "PATH=/bin"), now.end());
  unsetenv("CAUSTICD_EGL_DEVICE");
  unsetenv("CAUSTICD_MAX_SESSIONS");
  EXPECT_EQ(reloaded.port, 9300);
  EXPECT_EQ(reloaded.egl_device, ServerConfig{}.egl_device);
  EXPECT_EQ(reloaded.max_sessions, ServerConfig{}.max_sessions);
  EXPECT_TRUE(reloaded.warnings.empty());
}

// A value an operator chose and a later layer replaces is said, naming the
// key and both places; the shipped file's defaults replaced are not.
TEST(Config, AKeySetAgainInALaterPlaceIsWarnedAbout) {
  ServerConfig c;
  ConfigSources sources;
  const auto file = write_config("causticd_layers.conf",
                                 "port = 9000\nmax_sessions = 12\nlog_level = debug\nlog_level = info\n"
                                 "janus_admin_secret =\nframerate = 25\nwidth = 1024\nwidth = 512\n");
  load_config_file(c, file, &sources);
  // log_level and width, each written twice (width's first value the default:
  // twice in one file is a slip all the same).
  ASSERT_EQ(c.warnings.size(), 2u);
  EXPECT_NE(c.warnings[0].find("log_level"), std::string::npos) << c.warnings[0];
  EXPECT_NE(c.warnings[0].find("causticd_layers.conf:3"), std::string::npos) << c.warnings[0];
  EXPECT_NE(c.warnings[0].find("causticd_layers.conf:4"), std::string::npos) << c.warnings[0];
  EXPECT_NE(c.warnings[1].find("width: the value set at"), std::string::npos) << c.warnings[1];
  EXPECT_NE(c.warnings[1].find("causticd_layers.conf:7 is overridden by"), std::string::npos) << c.warnings[1];
  EXPECT_NE(c.warnings[1].find("causticd_layers.conf:8"), std::string::npos) << c.warnings[1];
  setenv("CAUSTICD_PORT", "9100", 1);
  setenv("CAUSTICD_MAX_SESSIONS", "4", 1);                               // the default was written: not said
  setenv("CAUSTICD_JANUS_ADMIN_SECRET", "0123456789abcdef0123", 1);      // an empty one was written: not said
  setenv("CAUSTICD_FRAMERATE", "25", 1);                                 // the same value: not said
  load_config_environment(c, &sources);
  unsetenv("CAUSTICD_PORT");
  unsetenv("CAUSTICD_MAX_SESSIONS");
  unsetenv("CAUSTICD_JANUS_ADMIN_SECRET");
  unsetenv("CAUSTICD_FRAMERATE");
  EXPECT_EQ(c.port, 9100);
  EXPECT_EQ(c.janus_admin_secret, "0123456789abcdef0123");
  ASSERT_EQ(c.warnings.size(), 3u);
  EXPECT_NE(c.warnings[2].find("port: the value set at"), std::string::npos) << c.warnings[2];
  EXPECT_NE(c.warnings[2].find("causticd_layers.conf:1"), std::string::npos) << c.warnings[2];
  EXPECT_NE(c.warnings[2].find("environment CAUSTICD_PORT"), std::string::npos) << c.warnings[2];
  // A flag over the environment's choice.
  set_config_value(c, "port", "9200");
  sources.set(c, "port", "9200", "--port");
  ASSERT_EQ(c.warnings.size(), 4u);
  EXPECT_NE(c.warnings[3].find("environment CAUSTICD_PORT is overridden by --port"), std::string::npos)
      << c.warnings[3];
  // Without a record of sources, nothing is said (check-config of one file).
  ServerConfig plain;
  load_config_file(plain, file);
  EXPECT_TRUE(plain.warnings.empty());
}

TEST(Config, AFileThatCannotBeReadSaysWhy) {
  // check-config and serve said "cannot read config file X" and no more.
  ServerConfig c;
  try {
    load_config_file(c, "/nonexistent-folder/causticd.conf");
    ADD_FAILURE() << "read";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/causticd.conf (No such file or directory)"),
              std::string::npos)
        << e.what();
  }
}
