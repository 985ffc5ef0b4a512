// SPDX-License-Identifier: LGPL-2.1-or-later
#include "notify.hpp"

#include "log.hpp"

#include <systemd/sd-daemon.h>

#include <ctime>

namespace caustic::server {

void notify(const std::string& assignments) {
  const int r = sd_notify(0, assignments.c_str());
  if (r < 0) log(Level::warning, "sd_notify failed: " + std::to_string(-r));
}

void notify_reloading() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  const auto usec = static_cast<unsigned long long>(now.tv_sec) * 1000000ull + now.tv_nsec / 1000;
  notify("RELOADING=1\nMONOTONIC_USEC=" + std::to_string(usec));
}

std::optional<std::chrono::microseconds> watchdog_interval() {
  uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) <= 0 || usec == 0) return std::nullopt;
  return std::chrono::microseconds(usec);
}

}  // namespace caustic::server
