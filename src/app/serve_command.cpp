// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd serve` and `causticd check-config`: the streaming server and the
// check of its configuration (docs/configuration.md, docs/operations.md).
#include "commands.hpp"

#include "caustic/gst/causticsrc.hpp"
#include "caustic/json_text.hpp"
#include "caustic/server/config.hpp"
#include "caustic/server/data_files.hpp"
#include "caustic/server/server.hpp"

#include <malloc.h>
#include <pthread.h>
#include <sys/resource.h>

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <regex>
#include <tuple>
#include <vector>

namespace caustic::app {
namespace {

struct ServeOptions {
  std::string config_file;
  // (config key, value, the flag that said it): the --set items in
  // command-line order, then the named flags, which apply after every --set
  // as render's do (the parser hands flags over in its own order, not the
  // line's). A key given twice is said, not silently the last.
  using Override = std::tuple<std::string, std::string, std::string>;
  std::vector<Override> assignments, flags;
  std::vector<std::string> ice_addresses;
  std::string instance;
  std::vector<std::string> environment;  // CAUSTICD_ variables as the process began
};

// Defaults, then the file, then CAUSTICD_* variables, then flags: what both
// the start and every SIGHUP read. Throws server::ConfigError.
server::ServerConfig read_config(const ServeOptions& opt) {
  server::ServerConfig config;
  server::ConfigSources sources;
  if (!opt.config_file.empty()) server::load_config_file(config, opt.config_file, &sources);
  server::load_config_environment(config, &sources, opt.environment);
  const auto set = [&](const std::string& key, const std::string& value, const std::string& where) {
    server::set_config_value(config, key, value);
    sources.set(config, key, value, where);
  };
  // A template unit's instance name: "<port>" or "<port>-gpu<N>".
  if (!opt.instance.empty()) {
    static const std::regex pattern("^([0-9]{1,5})(-gpu([0-9]{1,2}))?$");
    std::smatch m;
    if (!std::regex_match(opt.instance, m, pattern))
      throw server::ConfigError("--instance: must be <port> or <port>-gpu<N>, got \"" + opt.instance + "\"");
    set("port", m[1], "--instance");
    if (m[3].matched) set("egl_device", m[3], "--instance");
  }
  for (const auto& [key, value, flag] : opt.assignments) set(key, value, flag);
  for (const auto& [key, value, flag] : opt.flags) set(key, value, flag);
  if (!opt.ice_addresses.empty()) {
    std::string joined;
    for (const auto& a : opt.ice_addresses) joined += (joined.empty() ? "" : ",") + a;
    set("ice_addresses", joined, "--ice-address");
  }
  return config;
}

int run_serve(ServeOptions opt) {
  // A SIGHUP before the server's handler stands would end the process:
  // held until then (threads made meanwhile inherit the block and leave
  // the signal to this one), it reloads once the server listens.
  sigset_t hangup;
  sigemptyset(&hangup);
  sigaddset(&hangup, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &hangup, nullptr);
  // The environment as it began: the server sets CAUSTICD_EGL_DEVICE for
  // its GL contexts, which a reload must not read as the operator's choice.
  opt.environment = server::config_environment();
  server::ServerConfig config;
  try {
    config = read_config(opt);
    server::check_config(config, server::data_dir());  // the folders, before minutes of loading
  } catch (const server::ConfigError& e) {
    std::cerr << "causticd serve: " << e.what() << "\n";
    return bad_input;
  }
  // glibc gives threads arenas of their own and keeps what they free; with
  // a pipeline's threads per session, RSS then climbs with every session
  // that comes and goes. Two arenas keep it flat (docs/reliability.md).
  mallopt(M_ARENA_MAX, 2);
  // Connections and sessions need descriptors: take the hard limit, and say
  // when even that cannot hold the configured connections.
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) == 0) {
    files.rlim_cur = files.rlim_max;
    setrlimit(RLIMIT_NOFILE, &files);
    const rlim_t needed = static_cast<rlim_t>(config.max_connections) + 64 * static_cast<rlim_t>(config.max_sessions) + 64;
    if (files.rlim_cur != RLIM_INFINITY && files.rlim_cur < needed)
      std::cerr << "causticd serve: warning: max_connections " << config.max_connections << " and max_sessions "
                << config.max_sessions << " need about " << needed << " file descriptors; the limit is "
                << files.rlim_cur << " (raise LimitNOFILE)\n";
  }
  // Before any library speaks: their warnings go out as the server's events.
  server::route_library_messages();
  gst_init(nullptr, nullptr);
  if (!gst::register_elements()) {
    std::cerr << "causticd serve: cannot register the causticsrc element\n";
    return runtime_failure;
  }
  try {
    server::Server server(config, server::data_dir());
    pthread_sigmask(SIG_UNBLOCK, &hangup, nullptr);
    server.set_config_reloader([opt] { return read_config(opt); });
    const std::string url = server.listen();
    std::printf("listening on %s\n", url.c_str());
    std::fflush(stdout);
    server.run();
  } catch (const server::ConfigError& e) {
    // Found only once the server looks (a GPU that is not there).
    std::cerr << "causticd serve: " << e.what() << "\n";
    return bad_input;
  } catch (const std::exception& e) {
    std::cerr << "causticd serve: " << e.what() << "\n";
    return runtime_failure;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  return ok;
}

// Designs are kept under state_dir: a server that cannot write there
// streams the gallery with uploads off (and logs so); said here first.
// The folder need not exist yet: its nearest existing parent must let
// this user make it.
std::string state_problem(const server::ServerConfig& c) {
  if (!c.design_uploads) return "";
  const std::filesystem::path folder = server::state_folder(c);
  std::filesystem::path p = folder;
  std::error_code ec;
  while (!p.empty() && !std::filesystem::exists(p, ec)) p = p.parent_path();
  if (p.empty()) p = ".";
  if (std::filesystem::is_directory(p, ec) && ::access(p.c_str(), W_OK | X_OK) == 0) return "";
  return "state_dir: " + folder.string() + " cannot be made or written by this user: design uploads will be off";
}

int run_check_config(const std::string& file) {
  try {
    server::ServerConfig config;
    server::ConfigSources sources;
    server::load_config_file(config, file, &sources);
    server::check_config(config, server::data_dir());
    for (const auto& warning : config.warnings) std::cerr << "causticd check-config: warning: " << warning << "\n";
    if (const std::string problem = state_problem(config); !problem.empty())
      std::cerr << "causticd check-config: warning: " << problem << "\n";
  } catch (const server::ConfigError& e) {
    std::cerr << "causticd check-config: " << e.what() << "\n";
    return bad_input;
  } catch (const std::exception& e) {
    std::cerr << "causticd check-config: " << e.what() << "\n";
    return runtime_failure;
  }
  std::printf("%s: ok\n", file.c_str());
  return ok;
}

}  // namespace

std::function<int()> add_serve_command(CLI::App& app) {
  auto opt = std::make_shared<ServeOptions>();
  CLI::App* cmd = app.add_subcommand("serve", "Stream caustics to browsers (HTTP API, WebRTC)");
  cmd->add_option("--config", opt->config_file, "Config file (key = value lines)")->check(CLI::ExistingFile);
  const std::pair<const char*, const char*> flags[] = {
      {"--bind", "bind_address"},     {"--port", "port"},           {"--max-sessions", "max_sessions"},
      {"--codec", "codec"},           {"--bitrate", "bitrate_kbps"}, {"--framerate", "framerate"},
      {"--width", "width"},           {"--height", "height"},       {"--stun-server", "stun_server"},
      {"--turn-server", "turn_server"}, {"--idle-timeout", "idle_timeout_s"}, {"--scenes-dir", "scenes_dir"},
      {"--web-dir", "web_dir"},       {"--log-level", "log_level"}, {"--keyframe-interval", "keyframe_interval"},
      {"--egl-device", "egl_device"}};
  for (const auto& [flag, key] : flags) {
    const std::string k = key;
    cmd->add_option_function<std::string>(
        flag,
        [opt, k, f = std::string(flag)](const std::string& value) {
          // "" is refused, not taken as left out: --scenes-dir '' (an unset
          // variable) served the built-in gallery. --set key= keeps the key's
          // own meaning of an empty value.
          if (value.empty()) throw CLI::ValidationError(f, "must not be empty (leave the flag out for the default)");
          opt->flags.emplace_back(k, value, f);
        },
        "Overrides the config key " + k);
  }
  cmd->add_option_function<std::vector<std::string>>(
      "--set",
      [opt](const std::vector<std::string>& items) {
        for (const auto& item : items) {
          const auto eq = item.find('=');
          // As render's --set words it (an empty value after '=' is the key's own error).
          if (eq == std::string::npos)
            throw CLI::ValidationError("--set", "expected key=value, got " +
                                                    (item.empty() ? "nothing" : "\"" + printable_name(item) + "\""));
          opt->assignments.emplace_back(item.substr(0, eq), item.substr(eq + 1), "--set " + item.substr(0, eq));
        }
      },
      "Sets any config key: --set key=value (repeatable; docs/configuration.md)");
  cmd->add_option("--ice-address", opt->ice_addresses, "Local address ICE may use (repeatable; default: all)")
      ->check(not_empty());
  cmd->add_option("--instance", opt->instance, "Instance name of causticd@.service: <port> or <port>-gpu<N>")
      ->check(not_empty());
  return [cmd, opt] { return cmd->parsed() ? run_serve(*opt) : -1; };
}

std::function<int()> add_check_config_command(CLI::App& app) {
  auto file = std::make_shared<std::string>("/etc/causticd/causticd.conf");
  CLI::App* cmd = app.add_subcommand("check-config", "Validate a configuration file and exit");
  cmd->add_option("config", *file, "Config file (default /etc/causticd/causticd.conf)");
  return [cmd, file] { return cmd->parsed() ? run_check_config(*file) : -1; };
}

}  // namespace caustic::app
