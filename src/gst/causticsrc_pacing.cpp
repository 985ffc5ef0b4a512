// SPDX-License-Identifier: LGPL-2.1-or-later
// When causticsrc's frames leave, and with which picture. Frames keep a grid
// at the frame rate, each taking the newest picture when it is due; while
// the picture stays unchanged they go out only at the keep-alive rate
// (still-interval-ms). A picture finished during such a still spell, once a
// whole interval has passed since the last frame, leaves at once rather
// than at the next grid time (early-frames): the first change after a pause
// (a click, the start of a drag) reaches the viewer half an interval
// sooner on average, and the grid starts again from it. Frames never come
// closer than one interval, so the rate stays the configured one.
#include "causticsrc_state.hpp"

#include <utility>

namespace caustic::gst {
namespace {

GstClockTime frame_interval(const State& s) {
  return gst_util_uint64_scale(GST_SECOND, GST_VIDEO_INFO_FPS_D(&s.info), GST_VIDEO_INFO_FPS_N(&s.info));
}

// Running time of grid frame `index`.
GstClockTime grid_time(const State& s, guint64 index) {
  return s.first_due + gst_util_uint64_scale((index - s.first_index) * GST_SECOND, GST_VIDEO_INFO_FPS_D(&s.info),
                                             GST_VIDEO_INFO_FPS_N(&s.info));
}

// Waits for grid frame `due`, or less when a new picture may leave early:
// GST_FLOW_OK with *due moved to now in that case (the grid then starts
// again there), otherwise what the wait returned.
GstFlowReturn wait_for_frame(State& s, GstElement* element, GstClockTime* due) {
  for (;;) {
    const GstFlowReturn r = s.due_wait.wait(element, *due);
    if (r != GST_FLOW_CUSTOM_SUCCESS) return r;
    // A new picture: it may leave now if the stream has been still for an
    // interval and the grid frame is not about to leave anyway.
    if (!s.early_frames.load() || !s.last_sent) continue;
    const GstClockTime now = running_time_now(element), interval = frame_interval(s);
    if (now < s.last_sent_due + interval || now + interval / 4 >= *due) continue;
    s.first_due = *due = now;
    s.first_index = s.frame_index;
    return GST_FLOW_OK;
  }
}

}  // namespace

GstFlowReturn next_frame(State& s, GstElement* element, GstBuffer** picture, GstClockTime* due) {
  const GstClockTime interval = frame_interval(s);
  *picture = nullptr;
  // An unchanged picture waits for the next due frame that shows a new
  // one, or for its keep-alive, or for a key frame request: a still scene
  // then costs the encoder (nearly) nothing.
  for (;; ++s.frame_index) {
    *due = grid_time(s, s.frame_index);
    if (s.frame_index > 0)
      if (const GstFlowReturn r = wait_for_frame(s, element, due); r != GST_FLOW_OK) return r;
    *picture = s.worker->latest(std::chrono::nanoseconds(interval));
    if (!*picture) return GST_FLOW_FLUSHING;  // unlock(): the element is stopping
    // Frame 0 is stamped when its picture is ready and the rest follow at
    // the frame rate, so that a frame's timestamp is when it leaves:
    // GstBaseSrc then waits for exactly that time.
    if (s.frame_index == 0) {
      *due = s.first_due = running_time_now(element);
      s.first_index = 0;
    }
    if (s.still_interval == 0 || *picture != s.last_sent || *due >= s.last_sent_due + s.still_interval) break;
    if (s.send_next.exchange(false)) {
      GST_DEBUG_OBJECT(element, "frame %" G_GUINT64_FORMAT ": sent unchanged for a key frame request", s.frame_index);
      break;
    }
    gst_buffer_unref(std::exchange(*picture, nullptr));
    ++s.skipped;
  }
  if (s.still_interval > 0 && *picture != s.last_sent) {
    if (s.last_sent) gst_buffer_unref(s.last_sent);
    s.last_sent = gst_buffer_ref(*picture);
  }
  s.last_sent_due = *due;
  s.send_next = false;  // whatever leaves is the frame a key frame request waited for
  return GST_FLOW_OK;
}

void renegotiate(State& s, const GstVideoInfo& next) {
  const GstVideoInfo& now = s.info;
  const bool same = GST_VIDEO_INFO_FORMAT(&now) == GST_VIDEO_INFO_FORMAT(&next) &&
                    GST_VIDEO_INFO_WIDTH(&now) == GST_VIDEO_INFO_WIDTH(&next) &&
                    GST_VIDEO_INFO_HEIGHT(&now) == GST_VIDEO_INFO_HEIGHT(&next) &&
                    GST_VIDEO_INFO_FPS_N(&now) == GST_VIDEO_INFO_FPS_N(&next) &&
                    GST_VIDEO_INFO_FPS_D(&now) == GST_VIDEO_INFO_FPS_D(&next);
  if (s.worker && !same) {
    // The worker draws in the old format and size and the grid counts at
    // the old rate: the worker goes (its thread joined, its pictures with
    // it), and the grid starts again one old interval after the last frame.
    s.worker.reset();
    if (s.frame_index > 0) {
      s.first_due = s.last_sent_due + frame_interval(s);
      s.first_index = s.frame_index;
    }
  }
  s.info = next;
}

}  // namespace caustic::gst
