// SPDX-License-Identifier: LGPL-2.1-or-later
// How a session's webrtcbin gathers ICE candidates: no UPnP (a server has
// no NAT of its own to open), the configured UDP port range (instances on
// one host take disjoint ones, since media goes straight to each), and only
// the configured local addresses (tests pin it to loopback).
#pragma once

#include "caustic/server/config.hpp"

#include <gst/gst.h>

#include <string>
#include <vector>

namespace caustic::server {

/// Applies `config` to the ICE agent of `webrtcbin`; returns the addresses
/// of ice_addresses that the agent refused.
std::vector<std::string> configure_ice(GstElement* webrtcbin, const ServerConfig& config);

}  // namespace caustic::server
