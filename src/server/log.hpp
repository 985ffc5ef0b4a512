// SPDX-License-Identifier: LGPL-2.1-or-later
// One line per event on stderr, with the syslog priority prefix journald
// understands (<3> error .. <7> debug).
#pragma once

#include <string>

namespace caustic::server {

enum class Level { error = 3, warning = 4, notice = 5, info = 6, debug = 7 };

/// Events above `level` are dropped.
void set_log_level(Level level);
/// "error" .. "debug" (the config key log_level); throws std::invalid_argument.
Level level_from_name(const std::string& name);
void log(Level level, const std::string& message);

}  // namespace caustic::server
