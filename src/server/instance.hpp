// SPDX-License-Identifier: LGPL-2.1-or-later
// Being one of several instances behind a proxy (docs/scaling.md). A
// session lives on one instance, so its URLs carry that instance's number,
// /i/<n>/api/v1/sessions/..., and a proxy routes on the prefix alone (no
// hashing, no shared state). The instance answers both with and without
// its own prefix, so the same URLs work straight and through the proxy. New
// sessions go where capacity is free: the health answer says how much, and
// a capacity agent says it to HAProxy as a server weight.
#pragma once

#include "caustic/server/config.hpp"

#include <gio/gio.h>
#include <nlohmann/json.hpp>

#include <string>

namespace caustic::server {

struct ServerState;

/// "/i/<n>" for instance n, "" for an instance without a number.
std::string url_prefix(const ServerConfig& config);

enum class PathOwner { this_instance, other_instance };
/// Removes this instance's prefix from `path`; other_instance when the path
/// names another instance's prefix (a proxy that routed it wrongly).
PathOwner strip_instance_prefix(const ServerConfig& config, std::string& path);

/// Sessions this instance would still accept now: 0 while draining.
int free_sessions(const ServerState& s);

/// The HAProxy agent-check answer: "up ready <free>%" or "up drain".
std::string agent_answer(const ServerState& s);

/// Answers every TCP connection on bind_address:agent_port with
/// agent_answer() and closes it. Lives on the main loop's thread.
class CapacityAgent {
 public:
  /// Throws ListenError when the port cannot be bound.
  CapacityAgent(const ServerState& state, const std::string& address, int port);
  ~CapacityAgent();
  CapacityAgent(const CapacityAgent&) = delete;
  CapacityAgent& operator=(const CapacityAgent&) = delete;

 private:
  GSocketService* service_ = nullptr;
};

}  // namespace caustic::server
