// SPDX-License-Identifier: LGPL-2.1-or-later
// The playout-delay RTP header extension, sent as "no delay": a receiver
// that negotiates it (Chromium does) shows each frame as soon as it is
// decoded instead of holding it in a jitter buffer sized for smoothness.
// A viewer dragging a light wants the caustic to follow the hand, and the
// frames here arrive on a loopback or LAN path with little jitter. The page
// asks for the same with jitterBufferTarget = 0, which a browser may treat
// as a hint; the extension is the sender's word on every frame.
//
// Format (http://www.webrtc.org/experiments/rtp-hdrext/playout-delay):
// three bytes, a 12-bit minimum then a 12-bit maximum delay, in units of
// 10 ms, big-endian; both 0 here.
#pragma once

#include <gst/gst.h>

namespace caustic::server {

inline constexpr const char* kPlayoutDelayUri = "http://www.webrtc.org/experiments/rtp-hdrext/playout-delay";
/// Its id in the offer (a=extmap): the payloaders here carry no other.
inline constexpr guint kPlayoutDelayId = 1;

/// A new extension (floating reference, as gst_element_factory_make gives)
/// that writes a minimum and maximum of 0 into every packet, with `id`
/// (1 to 14, a one-byte header's range).
GstElement* make_playout_delay_extension(guint id);

/// Adds the extension to the payloader `pay` under kPlayoutDelayId;
/// webrtcbin then offers it (a=extmap) from the payloader's caps. False
/// when `pay` is not an RTP payloader.
bool add_playout_delay(GstElement* pay);

}  // namespace caustic::server
