// SPDX-License-Identifier: LGPL-2.1-or-later
// One event per call. Under systemd (stderr is the journal's stream) each
// goes to journald with its priority and the fields of a LogContext, so an
// operator can filter: journalctl -u causticd CAUSTICD_SESSION=<id>. On a
// terminal it is plain text; anywhere else one line with the syslog prefix
// (<3> error .. <7> debug) that other supervisors understand.
#pragma once

#include <string>

namespace caustic::server {

/// The values are syslog's (and journald's PRIORITY=) numbers.
enum class Level { error = 3, warning = 4, notice = 5, info = 6, debug = 7 };

/// Who an event is about; empty members are left out. journald field names
/// are in log.cpp's table (CAUSTICD_SESSION, CAUSTICD_SCENE, ...).
struct LogContext {
  std::string session;  ///< session id
  std::string scene;    ///< scene id
  std::string codec;    ///< vp8 | h264
  std::string peer;     ///< the client's address
};

/// Events above `level` are dropped.
void set_log_level(Level level);
/// "error" .. "debug" (the config key log_level); throws std::invalid_argument.
Level level_from_name(const std::string& name);
void log(Level level, const std::string& message, const LogContext& context = {});

}  // namespace caustic::server
