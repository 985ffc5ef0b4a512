// SPDX-License-Identifier: LGPL-2.1-or-later
// The systemd service protocol (sd_notify): readiness, reloading, stopping,
// status text and watchdog pings. Every call is a no-op when the process was
// not started with NOTIFY_SOCKET, so a plain `causticd serve` works alike.
#pragma once

#include <chrono>
#include <optional>
#include <string>

namespace caustic::server {

/// Sends newline-separated assignments, e.g. "READY=1\nSTATUS=listening".
void notify(const std::string& assignments);

/// "RELOADING=1" with the MONOTONIC_USEC systemd wants beside it.
void notify_reloading();

/// The interval the service manager expects watchdog pings in
/// (WatchdogSec=, via WATCHDOG_USEC); none when the watchdog is off.
std::optional<std::chrono::microseconds> watchdog_interval();

}  // namespace caustic::server
