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

}  // namespace caustic::server
