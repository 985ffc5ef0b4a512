// SPDX-License-Identifier: LGPL-2.1-or-later
// Setting a pipeline to NULL can leave an element inside it running.
// webrtcbin 1.22 negotiates on a thread of its own that it joins only after
// its children have gone down, and a transport bin that an offer makes in
// that window is synced to webrtcbin's state as it was a moment before: it
// can come up (its nicesrc locked in PLAYING, as webrtcbin's receive bin
// starts it) inside a webrtcbin already past its children. Nothing would
// stop it then, and the nicesrc would keep its ICE agent, the agent's
// sockets and their main contexts for the life of the process. That much
// is read from webrtcbin's code, never seen (the leak that was seen is a
// stopped receive bin holding itself: server/receive_bins.hpp). Once the
// first set_state(NULL) has returned, webrtcbin's thread has ended and
// nothing adds more: stop_pipeline then sets every element still above NULL
// to NULL itself, a locked one (which a bin's own state change skips) too.
#pragma once

#include <gst/gst.h>

namespace caustic::gst {

/// Sets `pipeline` to NULL, then each element inside it, at any depth, that
/// is still above NULL; returns how many those were (0 when the pipeline's
/// own state change stopped everything, as it almost always does).
int stop_pipeline(GstElement* pipeline);

}  // namespace caustic::gst
