// SPDX-License-Identifier: LGPL-2.1-or-later
#include "due_wait.hpp"

#include <utility>

namespace caustic::gst {

GstClockTime running_time_now(GstElement* element) {
  GstClock* clock = gst_element_get_clock(element);
  if (!clock) return 0;
  const GstClockTime now = gst_clock_get_time(clock), base = gst_element_get_base_time(element);
  gst_object_unref(clock);
  return now > base ? now - base : 0;
}

GstFlowReturn DueWait::wait(GstElement* element, GstClockTime due) {
  constexpr GstClockTime margin = 2 * GST_MSECOND;  // taking the picture is a reference count
  GstClock* clock = gst_element_get_clock(element);
  if (!clock) return GST_FLOW_OK;
  GstClockID id = nullptr;
  if (due > margin) id = gst_clock_new_single_shot_id(clock, gst_element_get_base_time(element) + due - margin);
  gst_object_unref(clock);
  if (!id) return GST_FLOW_OK;
  bool wait = false;
  {
    std::lock_guard lock(lock_);
    if ((wait = !flushing_ && !interrupted_)) pending_ = id;
  }
  if (wait) gst_clock_id_wait(id, nullptr);
  std::lock_guard lock(lock_);
  pending_ = nullptr;
  gst_clock_id_unref(id);
  if (flushing_) return GST_FLOW_FLUSHING;
  const bool early = std::exchange(interrupted_, false);
  return early ? GST_FLOW_CUSTOM_SUCCESS : GST_FLOW_OK;
}

void DueWait::interrupt() {
  std::lock_guard lock(lock_);
  interrupted_ = true;
  if (pending_) gst_clock_id_unschedule(pending_);
}

void DueWait::unlock() {
  std::lock_guard lock(lock_);
  flushing_ = true;
  if (pending_) gst_clock_id_unschedule(pending_);
}

void DueWait::unlock_stop() {
  std::lock_guard lock(lock_);
  flushing_ = false;
}

}  // namespace caustic::gst
