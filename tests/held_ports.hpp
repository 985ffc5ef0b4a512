// SPDX-License-Identifier: LGPL-2.1-or-later
// A port picked by a test and handed to another program (a proxy, the
// capacity agent) is free when picked, not when the program binds it: ctest
// runs tests side by side, and any of their processes may take it between
// the two. What answers there then is not the program under test, so the
// test asks the kernel who holds the port, and tries again on a new one.
#pragma once

#include "helper_processes.hpp"

#include <glib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace caustic::testing {

/// The inodes of the TCP sockets listening on local port `port` (IPv4 and
/// IPv6, any address), from the kernel's tables.
inline std::vector<unsigned long> tcp_listeners_on(int port) {
  std::vector<unsigned long> inodes;
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::ifstream in(table);
    std::string line;
    std::getline(in, line);  // the column names
    while (std::getline(in, line)) {
      // sl local_address rem_address st tx:rx tr:when retrnsmt uid timeout inode
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout;
      unsigned long inode = 0;
      if (!(fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode)) continue;
      const auto colon = local.rfind(':');
      if (state == "0A" && colon != std::string::npos && std::stoi(local.substr(colon + 1), nullptr, 16) == port)
        inodes.push_back(inode);
    }
  }
  return inodes;
}

/// The inodes of the sockets process `pid` has open (none once it exited).
inline std::set<unsigned long> socket_inodes_of(const std::string& pid) {
  std::set<unsigned long> inodes;
  std::error_code error;
  std::filesystem::directory_iterator fd("/proc/" + pid + "/fd", error);
  for (; !error && fd != std::filesystem::directory_iterator(); fd.increment(error)) {
    std::error_code gone;  // a descriptor closed meanwhile
    const std::string target = std::filesystem::read_symlink(fd->path(), gone).string();
    if (!gone && target.rfind("socket:[", 0) == 0) inodes.insert(std::stoul(target.substr(8)));
  }
  return inodes;
}

/// Whether process `pid` listens on TCP port `port` and nothing else does
/// (SO_REUSEPORT lets processes share one: HAProxy sets it).
inline bool holds_port(const std::string& pid, int port) {
  if (pid.empty()) return false;
  const auto listeners = tcp_listeners_on(port);
  const auto own = socket_inodes_of(pid);
  return !listeners.empty() &&
         std::all_of(listeners.begin(), listeners.end(), [&](unsigned long inode) { return own.count(inode) > 0; });
}

/// Whether `child` comes to hold `port` within `timeout_ms`; false at once
/// when it exits (a program that cannot bind its port stops).
inline bool comes_to_hold(const ChildProcess& child, int port, int timeout_ms = 10000) {
  for (int waited = 0; waited < timeout_ms; waited += 50, g_usleep(50000)) {
    const std::string pid = child.pid();
    if (pid.empty()) return false;
    if (holds_port(pid, port)) return true;
  }
  return false;
}

/// Starts a program on a port of the test's choosing: `start(port)` starts
/// it and says whether it is what holds the port (holds_port). A port taken
/// meanwhile gets a new one from `pick`, three tries in all. The port that
/// worked, or 0.
inline int start_on_a_free_port(const std::function<bool(int)>& start, const std::function<int()>& pick = free_port) {
  for (int attempt = 0; attempt < 3; ++attempt)
    if (const int port = pick(); start(port)) return port;
  return 0;
}

}  // namespace caustic::testing
