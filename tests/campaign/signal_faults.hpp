// SPDX-License-Identifier: LGPL-2.1-or-later
// Bad messages on a session's signalling WebSocket (part of "malformed").
#pragma once

#include "kinds.hpp"

namespace campaign {

void run_signal_faults(const Options& options, KindReport& report, ServerProcess& server, const std::string& scene);

}  // namespace campaign
