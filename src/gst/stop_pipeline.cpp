// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/gst/stop_pipeline.hpp"

#include "caustic/gst/bin_elements.hpp"

#include <vector>

namespace caustic::gst {

int stop_pipeline(GstElement* pipeline) {
  if (!pipeline) return 0;
  gst_element_set_state(pipeline, GST_STATE_NULL);
  // Collected first, then stopped: a bin that stops may remove pads and
  // children, which would resync a walk still under way.
  const std::vector<GstElement*> running = bin_elements(pipeline, true, [](GstElement* element) {
    GST_OBJECT_LOCK(element);
    const bool up = GST_STATE(element) != GST_STATE_NULL;
    GST_OBJECT_UNLOCK(element);
    return up;
  });
  // A bin that stops its own children (webrtcbin's receive bin unlocks and
  // stops its nicesrc) may leave an element later in the list at NULL
  // already: setting it again does nothing.
  for (GstElement* e : running) {
    gst_element_set_state(e, GST_STATE_NULL);
    gst_object_unref(e);
  }
  return static_cast<int>(running.size());
}

}  // namespace caustic::gst
