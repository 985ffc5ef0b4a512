// SPDX-License-Identifier: LGPL-2.1-or-later
// Pad probes on a session pipeline: encode time and frames sent (metrics),
// and, per RTP timestamp, the parameter version its frame shows.
#pragma once

#include "metrics.hpp"

#include <gst/gst.h>

#include <cstdint>
#include <functional>

namespace caustic::server {

/// Called on a streaming thread once per new RTP timestamp, with the
/// parameter version and fidelity level (0 full, 1 preview) of its frame.
using FrameTold = std::function<void(guint32 rtp_timestamp, std::uint64_t version, std::uint32_t level)>;

/// Needs elements named "encoder" and "pay" in `pipeline`.
void install_frame_probes(GstElement* pipeline, Metrics* metrics, FrameTold tell);

/// Passes a viewer's key frame requests (PLI/FIR, a force-key-unit event
/// that the element "encoder" keeps to itself) on to causticsrc "src" as
/// well, which then sends a frame even if its picture is unchanged: with
/// frames only on change, the encoder would otherwise wait for one.
void pass_key_unit_requests(GstElement* pipeline);

}  // namespace caustic::server
