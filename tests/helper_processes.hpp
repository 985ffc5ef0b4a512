// SPDX-License-Identifier: LGPL-2.1-or-later
// What the tests that run other servers beside causticd (proxies, Janus)
// share: a free loopback port, the shipped configuration files read and
// adapted, and a child process that is stopped when the test ends.
#pragma once

#include <gio/gio.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace caustic::testing {

/// The local port of IPv4 socket `fd` (0 when it has none).
inline int port_of(int fd) {
  sockaddr_in a{};
  socklen_t size = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size);
  return ntohs(a.sin_port);
}

/// A loopback TCP port free right now (the kernel's pick, then released).
inline int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  const int port = port_of(fd);
  ::close(fd);
  return port;
}

/// "first-last": `count` UDP ports (at most 64) free right now, in a block
/// picked at random below the kernel's range for port 0, where nothing takes
/// them by chance: a program told to use a range keeps to it while tests run
/// side by side. "" after 20 tries.
inline std::string free_udp_block(int count) {
  static unsigned seed = static_cast<unsigned>(::getpid()) ^ static_cast<unsigned>(g_get_monotonic_time());
  for (int attempt = 0; attempt < 20; ++attempt) {
    const int first = 20000 + 64 * static_cast<int>(::rand_r(&seed) % 180);  // up to 31,583
    bool free = true;
    for (int port = first; port < first + count && free; ++port) {
      const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_port = htons(static_cast<std::uint16_t>(port));
      free = fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
      if (fd >= 0) ::close(fd);
    }
    if (free) return std::to_string(first) + "-" + std::to_string(first + count - 1);
  }
  return "";
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Replaces every `from` in `text`; a shipped file that no longer has it
/// fails the test (the test would otherwise run a configuration unadapted).
inline void replace_all(std::string& text, const std::string& from, const std::string& to) {
  std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the shipped configuration no longer has \"" << from << "\"";
  for (; at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
}

/// The installed program's path, or "" when it is not installed.
inline std::string find_program(const std::string& name) {
  for (const char* dir : {"/usr/sbin", "/usr/bin", "/sbin", "/bin"})
    if (std::filesystem::exists(std::filesystem::path(dir) / name)) return (std::filesystem::path(dir) / name).string();
  return "";
}

/// Runs a shell command line to its end; its exit status (-1 if it did not
/// exit), with stdout and stderr in `output`.
inline int run_command(const std::string& command, std::string* output) {
  gchar *out = nullptr, *err = nullptr;
  gint status = 0;
  GError* error = nullptr;
  const gchar* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  if (!g_spawn_sync(nullptr, const_cast<gchar**>(argv), nullptr, G_SPAWN_DEFAULT, nullptr, nullptr, &out, &err, &status,
                    &error)) {
    *output = error->message;
    g_error_free(error);
    return -1;
  }
  *output = std::string(out ? out : "") + (err ? err : "");
  g_free(out);
  g_free(err);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A child process, stopped (SIGTERM, then waited for) when this goes.
class ChildProcess {
 public:
  ChildProcess() = default;
  explicit ChildProcess(const std::vector<std::string>& argv) { start(argv); }
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  void start(const std::vector<std::string>& argv) {
    stop();
    std::vector<const char*> args;
    for (const auto& a : argv) args.push_back(a.c_str());
    args.push_back(nullptr);
    GError* error = nullptr;
    process_ = g_subprocess_newv(args.data(), G_SUBPROCESS_FLAGS_NONE, &error);
    if (!process_) {
      ADD_FAILURE() << argv[0] << ": " << error->message;
      g_error_free(error);
    }
  }
  /// SIGTERM, and SIGCONT after it so that a child left frozen (a test that
  /// failed between SIGSTOP and SIGCONT) takes it; SIGKILL after 10 s.
  void stop() {
    if (!process_) return;
    g_subprocess_send_signal(process_, SIGTERM);
    g_subprocess_send_signal(process_, SIGCONT);
    // GLib's worker thread reaps the child; its identifier goes then.
    for (int waited = 0; waited < 10000 && g_subprocess_get_identifier(process_); waited += 20) g_usleep(20000);
    if (g_subprocess_get_identifier(process_)) g_subprocess_force_exit(process_);
    g_subprocess_wait(process_, nullptr, nullptr);
    g_object_unref(process_);
    process_ = nullptr;
  }
  bool running() const { return process_ != nullptr; }
  /// The process id as text; "" once it exited (or before it started).
  std::string pid() const {
    const char* id = process_ ? g_subprocess_get_identifier(process_) : nullptr;
    return id ? id : "";
  }
  /// SIGSTOP freezes it (a server that takes long to answer), SIGCONT thaws it.
  void signal(int sig) {
    if (process_) g_subprocess_send_signal(process_, sig);
  }

 private:
  GSubprocess* process_ = nullptr;
};

}  // namespace caustic::testing
