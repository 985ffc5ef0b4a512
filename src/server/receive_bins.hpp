// SPDX-License-Identifier: LGPL-2.1-or-later
// webrtcbin 1.22's receive bin blocks its nicesrc's pad until ICE connects,
// and (re)makes that block whenever its ICE transport's state changes; the
// block holds a reference to the bin itself. Its READY to NULL frees the
// block, but a state change after it makes a new one that nothing frees:
// the bin, its nicesrc, the ICE agent, the agent's sockets and their main
// contexts then stay for the life of the process. A session deleted while
// webrtcbin applies its offer does that (the offer's task starts gathering
// on webrtcbin's thread after the bin is down), about once in a thousand
// create-and-delete cycles on a loaded machine (docs/reliability.md); so
// could any ICE state change of a connected session's agent after its stop.
#pragma once

#include <gst/gst.h>

namespace caustic::server {

/// For a webrtcbin whose pipeline has been set to NULL (its thread has
/// ended): cuts each receive bin's handler of its ICE transport's state, so
/// no later change makes a block, then frees a block already made by taking
/// the bin through READY and back to NULL (its own way of freeing it).
/// Returns how many bins held one. Safe on an element that is not a
/// webrtcbin or has no transports yet (returns 0).
int release_receive_bins(GstElement* webrtcbin);

}  // namespace caustic::server
