// SPDX-License-Identifier: LGPL-2.1-or-later
#include "log.hpp"

#include <atomic>
#include <cstdio>
#include <stdexcept>

namespace caustic::server {
namespace {
std::atomic<int> threshold{static_cast<int>(Level::info)};
}

void set_log_level(Level level) { threshold = static_cast<int>(level); }

Level level_from_name(const std::string& name) {
  if (name == "error") return Level::error;
  if (name == "warning") return Level::warning;
  if (name == "notice") return Level::notice;
  if (name == "info") return Level::info;
  if (name == "debug") return Level::debug;
  throw std::invalid_argument("unknown log level \"" + name + "\"");
}

void log(Level level, const std::string& message) {
  if (static_cast<int>(level) > threshold) return;
  // One fprintf per line: lines from several threads do not interleave.
  std::string line = message;
  for (auto& ch : line)
    if (ch == '\n') ch = ' ';
  std::fprintf(stderr, "<%d>%s\n", static_cast<int>(level), line.c_str());
}

}  // namespace caustic::server
