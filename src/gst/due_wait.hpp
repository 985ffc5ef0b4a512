// SPDX-License-Identifier: LGPL-2.1-or-later
// When causticsrc's frames leave. GstBaseSrc asks a live source for its next
// frame as soon as the previous one left, a whole interval before it is due,
// and then holds it until then; waiting here first lets the frame take the
// newest picture instead of one that is an interval old. A picture finished
// while the stream stands still need not wait for the next frame time at
// all: interrupt() cuts the wait short (causticsrc_pacing.cpp).
#pragma once

#include <gst/gst.h>

#include <mutex>

namespace caustic::gst {

/// The running time of `element` now (0 without a clock).
GstClockTime running_time_now(GstElement* element);

/// An interruptible wait on the element's clock.
class DueWait {
 public:
  /// Waits until just before running time `due` (at once without a clock or
  /// when it has passed). GST_FLOW_FLUSHING when unlock() cut it short,
  /// GST_FLOW_CUSTOM_SUCCESS when interrupt() did (during it or since the
  /// last wait ended).
  GstFlowReturn wait(GstElement* element, GstClockTime due);
  /// Ends the current wait early, or the next one at once (a new picture).
  void interrupt();
  /// Ends the current wait and refuses new ones until unlock_stop()
  /// (GstBaseSrc's unlock and unlock_stop, from another thread).
  void unlock();
  void unlock_stop();

 private:
  std::mutex lock_;
  GstClockID pending_ = nullptr;  // the wait unlock() cuts short
  bool flushing_ = false;
  bool interrupted_ = false;
};

}  // namespace caustic::gst
