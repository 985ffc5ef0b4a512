#include "commands.hpp"

#include "caustic/gst/causticsrc.hpp"
#include "caustic/server/config.hpp"
#include "caustic/server/data_files.hpp"
#include "caustic/server/server.hpp"

#include <cstdio>
#include <iostream>
#include <map>
#include <memory>

namespace caustic::app {
namespace {

struct ServeOptions {
  std::string config_file;
  std::map<std::string, std::string> overrides;  // config key -> value from flags
  std::vector<std::string> ice_addresses;
};

int run_serve(const ServeOptions& opt) {
  server::ServerConfig config;
  try {
    if (!opt.config_file.empty()) server::load_config_file(config, opt.config_file);
    server::load_config_environment(config);
    for (const auto& [key, value] : opt.overrides) server::set_config_value(config, key, value);
    if (!opt.ice_addresses.empty()) {
      std::string joined;
      for (const auto& a : opt.ice_addresses) joined += (joined.empty() ? "" : ",") + a;
      server::set_config_value(config, "ice_addresses", joined);
    }
  } catch (const server::ConfigError& e) {
    std::cerr << "causticd serve: " << e.what() << "\n";
    return bad_input;
  }
  gst_init(nullptr, nullptr);
  if (!gst::register_elements()) {
    std::cerr << "causticd serve: cannot register the causticsrc element\n";
    return runtime_failure;
  }
  try {
    server::Server server(config, server::data_dir());
    const std::string url = server.listen();
    std::printf("listening on %s\n", url.c_str());
    std::fflush(stdout);
    server.run();
  } catch (const std::exception& e) {
    std::cerr << "causticd serve: " << e.what() << "\n";
    return runtime_failure;
  }
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
      {"--web-dir", "web_dir"}};
  for (const auto& [flag, key] : flags) {
    const std::string k = key;
    cmd->add_option_function<std::string>(
        flag, [opt, k](const std::string& value) { opt->overrides[k] = value; },
        "Overrides the config key " + k);
  }
  cmd->add_option("--ice-address", opt->ice_addresses, "Local address ICE may use (repeatable; default: all)");
  return [cmd, opt] { return cmd->parsed() ? run_serve(*opt) : -1; };
}

}  // namespace caustic::app
