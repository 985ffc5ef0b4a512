// SPDX-License-Identifier: LGPL-2.1-or-later
// Pad probes on a session pipeline: encode time and frames sent (metrics),
// and, per RTP timestamp, the parameter version its frame shows.
#pragma once

#include "metrics.hpp"

#include <gst/gst.h>

#include <cstdint>
#include <functional>

namespace caustic::server {

/// What a frame shows (its CausticFrameMeta).
struct FrameFacts {
  std::uint64_t version = 0;     ///< parameter version
  std::uint32_t level = 0;       ///< fidelity level: 0 full, 1 preview
  std::uint64_t water_step = 0;  ///< the water's solver step (0: no water)
};

/// Called on a streaming thread once per new RTP timestamp, with what its frame shows.
using FrameTold = std::function<void(guint32 rtp_timestamp, const FrameFacts& frame)>;

/// Needs elements named "encoder" and "pay" in `pipeline`.
void install_frame_probes(GstElement* pipeline, Metrics* metrics, FrameTold tell);

/// Passes a viewer's key frame requests (PLI/FIR, a force-key-unit event
/// that the element "encoder" keeps to itself) on to causticsrc "src" as
/// well, which then sends a frame even if its picture is unchanged: with
/// frames only on change, the encoder would otherwise wait for one.
void pass_key_unit_requests(GstElement* pipeline);

}  // namespace caustic::server
