// SPDX-License-Identifier: LGPL-2.1-or-later
// Starts the causticd under test with a generated config file and watches
// the process: whether it lives, how many descriptors and threads it holds.
#pragma once

#include <sys/types.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "report.hpp"

namespace campaign {

using Config = std::vector<std::pair<std::string, std::string>>;

class ServerProcess {
 public:
  ServerProcess(std::string binary, std::string folder) : binary_(std::move(binary)), folder_(std::move(folder)) {}
  ~ServerProcess() { stop(); }

  // Writes the config, drops keys this binary refuses (each one a failed
  // check: the contract names them) and waits for "listening on".
  bool start(Config config, KindReport& report);
  // SIGTERM (twice when draining), then SIGKILL after a bounded wait.
  void stop();
  // False once the process exited; `why` says how.
  bool alive(std::string* why = nullptr);
  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  int descriptors() const;  // entries of /proc/PID/fd, -1 when unreadable
  int threads() const;      // Threads: of /proc/PID/status
  // The descriptors by kind ("tcp CLOSE_WAIT", "udp", "unix", "netlink",
  // "anon_inode:[eventfd]", a file's path), counted: a leak check that
  // fails says what was left behind, not only how many.
  std::map<std::string, int> descriptor_kinds() const;
  // The threads by name (/proc/PID/task/*/comm), counted: whose thread a
  // leak kept, or that none was kept.
  std::map<std::string, int> thread_names() const;
  std::string log_tail(size_t bytes = 2000) const;

 private:
  std::string binary_;
  std::string folder_;
  pid_t pid_ = -1;
  int port_ = 0;
  int exit_status_ = 0;
  bool exited_ = false;
  int starts_ = 0;  // serial of the latest start, names its logs
  bool started_once_ = false;
  std::vector<std::string> refused_keys_;  // learnt on the first start
};

// "tcp CLOSE_WAIT +3, anon_inode:[eventfd] +2": the kinds `after` holds more
// of (descriptors or threads alike).
std::string descriptor_growth(const std::map<std::string, int>& before, const std::map<std::string, int>& after);

// Raises RLIMIT_NOFILE to its hard limit (inherited by the server too).
long raise_descriptor_limit();

// GET a path with Connection: close; the body, or "" on any failure.
std::string fetch_body(int port, const std::string& target, const std::string& token = "", int* status = nullptr);

// The "sessions" of /api/v1/health, or -1.
int session_count(int port);

}  // namespace campaign
