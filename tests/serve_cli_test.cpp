// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd check-config` and `causticd serve` refusing what they are given:
// exit 2 naming the key, before anything starts (or 1 naming the setting
// when a socket cannot be bound, which a restart may mend). Each run is
// bounded by `timeout`; nothing listens for long.
#include <glib.h>
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

namespace fs = std::filesystem;

namespace {

// Runs `causticd ARGS` to its end (`timeout` bounds a server that would
// start), with `env` (NAME=VALUE ...) added to its environment: its exit
// status (-1 when killed) and its stdout and stderr.
int run_causticd(const std::string& args, std::string* output, const std::string& env = "") {
  gchar *out = nullptr, *err = nullptr;
  gint status = 0;
  const std::string command = "env " + env + " timeout 120 " + CAUSTICD_BINARY + " " + args;
  const bool ran = g_spawn_command_line_sync(command.c_str(), &out, &err, &status, nullptr);
  *output = std::string(out ? out : "") + (err ? err : "");
  g_free(out);
  g_free(err);
  return ran && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(CheckConfig, AcceptsTheShippedFileAndNamesTheKeyOfABrokenOne) {
  auto run = [](const std::string& args, std::string* output) { return run_causticd("check-config " + args, output); };
  std::string output;
  EXPECT_EQ(run(CAUSTIC_SOURCE_DIR "/systemd/causticd.conf", &output), 0) << output;
  EXPECT_NE(output.find(": ok"), std::string::npos) << output;
  const fs::path dir = fs::temp_directory_path() / "causticd_check_config";
  fs::create_directories(dir);
  const std::pair<const char*, const char*> broken[] = {
      {"port = 80800", "port"}, {"codec = av1", "codec"}, {"scenes_dir = /nonexistent", "scenes_dir"},
      {"colour = red", "colour: unknown key"}, {"log_level = loud", "log_level"}, {"port", "expected key = value"},
      {"bind_address = 256.0.0.1", "bind_address"}};
  for (const auto& [line, named] : broken) {
    std::ofstream(dir / "broken.conf") << "# a comment\n" << line << "\n";
    EXPECT_EQ(run((dir / "broken.conf").string(), &output), 2) << line;
    EXPECT_NE(output.find(named), std::string::npos) << output;
    if (std::string(named) != "scenes_dir") {  // the folder check has no line to name
      EXPECT_NE(output.find("broken.conf:2"), std::string::npos) << output;
    }
  }
  EXPECT_EQ(run("/nonexistent.conf", &output), 2);
  EXPECT_NE(output.find("/nonexistent.conf"), std::string::npos) << output;
  // A kernel file that says it is regular and then waits on a read held
  // check-config until killed; it is refused unread. Only root may open it.
  if (fs::exists("/proc/kmsg") && geteuid() == 0) {
    EXPECT_EQ(run("/proc/kmsg", &output), 2) << output;
    EXPECT_NE(output.find("/proc/kmsg is a pipe, socket, device or kernel file"), std::string::npos) << output;
  }
  // A key written twice: the first is not silently dropped.
  std::ofstream(dir / "twice.conf") << "port = 9000\nport = 9001\n";
  EXPECT_EQ(run((dir / "twice.conf").string(), &output), 0) << output;
  EXPECT_NE(output.find("warning: port: the value set at " + (dir / "twice.conf").string() + ":1 is overridden by " +
                        (dir / "twice.conf").string() + ":2"),
            std::string::npos)
      << output;
  // A state folder that cannot be made (a file stands where it would be):
  // valid, but uploads would be off, and the key is named.
  std::ofstream(dir / "a-file") << "x";
  std::ofstream(dir / "state.conf") << "state_dir = " << (dir / "a-file" / "state").string() << "\n";
  EXPECT_EQ(run((dir / "state.conf").string(), &output), 0) << output;
  EXPECT_NE(output.find("warning: state_dir: " + (dir / "a-file" / "state").string() + " cannot be made"),
            std::string::npos)
      << output;
  std::ofstream(dir / "state.conf") << "state_dir = " << (dir / "state").string() << "\n";
  EXPECT_EQ(run((dir / "state.conf").string(), &output), 0) << output;
  EXPECT_EQ(output.find("state_dir"), std::string::npos) << output;
  // Inside the served folder, the designs' records (each with its delete
  // token) were static files for anyone: refused, naming the key.
  fs::create_directories(dir / "web");
  std::ofstream(dir / "state.conf") << "web_dir = " << (dir / "web").string() << "\nstate_dir = "
                                    << (dir / "web" / "." / "state").string() << "\n";
  EXPECT_EQ(run((dir / "state.conf").string(), &output), 2) << output;
  EXPECT_NE(output.find("state_dir: " + (dir / "web" / "state").string() + " lies inside web_dir"), std::string::npos)
      << output;
  fs::remove_all(dir);
}

TEST(Serve, AGpuThatIsNotThereIsAConfigurationErrorThatNamesIt) {
  // Exit 2 (RestartPreventExitStatus=2 in the units: no restart loop), the
  // key and the GPU named, not "no usable scene" blaming the scenes folder.
  // No host here has ten GPUs; `timeout` bounds a server that would start.
  for (const char* args : {"--egl-device 9", "--instance 18099-gpu9"}) {
    std::string output;
    EXPECT_EQ(run_causticd(std::string("serve --bind 127.0.0.1 --port 0 ") + args, &output), 2) << args << ": " << output;
    EXPECT_NE(output.find("egl_device: GPU 9 not found"), std::string::npos) << output;
    EXPECT_EQ(output.find("no usable scene"), std::string::npos) << output;
  }
  // The platform variable alike: a name no EGL offers (any command), and a
  // device platform on a host without a GPU.
  for (const char* command : {"serve --bind 127.0.0.1 --port 0", "check-config"}) {
    std::string output;
    EXPECT_EQ(run_causticd(command, &output, "CAUSTICD_EGL_PLATFORM=vulkan"), 2) << command << ": " << output;
    EXPECT_NE(output.find("CAUSTICD_EGL_PLATFORM must be automatic, device or surfaceless, got \"vulkan\""),
              std::string::npos)
        << output;
  }
  if (fs::exists("/dev/dri") || fs::exists("/dev/nvidia0")) return;  // a GPU may be there: serve would start
  std::string output;
  EXPECT_EQ(run_causticd("serve --bind 127.0.0.1 --port 0", &output, "CAUSTICD_EGL_PLATFORM=device"), 2) << output;
  EXPECT_NE(output.find("CAUSTICD_EGL_PLATFORM: no hardware EGL device"), std::string::npos) << output;
  EXPECT_EQ(output.find("no usable scene"), std::string::npos) << output;
}

TEST(Serve, FoldersAndAddressesAreCheckedAsCheckConfigChecksThem) {
  // Before the gallery loads, exit 2 naming the key: what check-config says.
  const std::pair<const char*, const char*> bad[] = {{"--web-dir /nonexistent", "web_dir: /nonexistent is not a folder"},
                                                     {"--scenes-dir /nonexistent", "scenes_dir"},
                                                     {"--bind 999.1.1.1", "bind_address: must be an IP address"},
                                                     // Once "noequals: unknown key", and a value quoted as """".
                                                     {"--set noequals", "--set: expected key=value, got \"noequals\""},
                                                     {"--set port=", "port: must be an integer in [0, 65535], got an empty value"}};
  for (const auto& [args, named] : bad) {
    std::string output;
    EXPECT_EQ(run_causticd(std::string("serve --port 0 ") + args, &output), 2) << args << ": " << output;
    EXPECT_NE(output.find(named), std::string::npos) << output;
    EXPECT_EQ(output.find("listening"), std::string::npos) << output;
  }
}

TEST(Serve, ADataFolderThatIsNotThereIsAConfigurationErrorThatNamesIt) {
  // The data folder comes from CAUSTICD_DATA_DIR or from beside the
  // executable; a copy of the binary elsewhere has neither. Exit 2 naming
  // the variable, from serve and check-config alike, not an abort.
  const fs::path dir = fs::temp_directory_path() / "causticd_no_data";
  fs::create_directories(dir / "bin");
  fs::copy_file(CAUSTICD_BINARY, dir / "bin/causticd", fs::copy_options::overwrite_existing);
  const std::pair<std::string, const char*> cases[] = {
      {"env -u CAUSTICD_DATA_DIR " + (dir / "bin/causticd").string() + " serve --bind 127.0.0.1 --port 0",
       "CAUSTICD_DATA_DIR: not set"},
      {"env -u CAUSTICD_DATA_DIR " + (dir / "bin/causticd").string() + " check-config " CAUSTIC_SOURCE_DIR
       "/systemd/causticd.conf",
       "CAUSTICD_DATA_DIR: not set"},
      {"env CAUSTICD_DATA_DIR=/nonexistent " + std::string(CAUSTICD_BINARY) + " serve --bind 127.0.0.1 --port 0",
       "CAUSTICD_DATA_DIR: /nonexistent is not a folder"}};
  for (const auto& [command, named] : cases) {
    gchar *out = nullptr, *err = nullptr;
    gint status = 0;
    ASSERT_TRUE(g_spawn_command_line_sync(("timeout 120 " + command).c_str(), &out, &err, &status, nullptr));
    const std::string output = std::string(out ? out : "") + (err ? err : "");
    g_free(out);
    g_free(err);
    ASSERT_TRUE(WIFEXITED(status)) << command << ": " << output;
    EXPECT_EQ(WEXITSTATUS(status), 2) << command << ": " << output;
    EXPECT_NE(output.find(named), std::string::npos) << output;
    EXPECT_EQ(output.find("listening"), std::string::npos) << output;
  }
  fs::remove_all(dir);
}

// A socket that cannot be bound names the setting in its way: the port
// (taken here by the test), the agent's port, or an address not on this
// host. Exit 1, not 2: a restart may mend it (the port freed, the address
// up), and systemd retries 1 but not 2 (docs/operations.md).
TEST(Serve, AServerThatCannotListenNamesTheSettingInItsWay) {
  const int held = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(held, 0);
  sockaddr_in at{};
  at.sin_family = AF_INET;
  at.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof at;
  ASSERT_EQ(::bind(held, reinterpret_cast<sockaddr*>(&at), sizeof at), 0);
  ASSERT_EQ(::listen(held, 1), 0);
  ASSERT_EQ(::getsockname(held, reinterpret_cast<sockaddr*>(&at), &size), 0);
  const std::string port = std::to_string(ntohs(at.sin_port));
  const auto expect = [](const std::string& args, const std::string& said) {
    std::string output;
    EXPECT_EQ(run_causticd(args, &output), 1) << output;
    EXPECT_NE(output.find(said), std::string::npos) << output;
  };
  expect("serve --bind 127.0.0.1 --port " + port, "port: cannot listen on 127.0.0.1:" + port + ": ");
  expect("serve --bind 127.0.0.1 --port 0 --set agent_port=" + port,
         "agent_port: cannot listen on 127.0.0.1:" + port + ": ");
  // 192.0.2.1 is for documentation (RFC 5737): no host holds it.
  expect("serve --bind 192.0.2.1 --port 0", "bind_address: cannot listen on 192.0.2.1:0: ");
  ::close(held);
}
