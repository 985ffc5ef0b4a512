// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/gst/stop_pipeline.hpp"

#include <vector>

namespace caustic::gst {

int stop_pipeline(GstElement* pipeline) {
  if (!pipeline) return 0;
  gst_element_set_state(pipeline, GST_STATE_NULL);
  if (!GST_IS_BIN(pipeline)) return 0;
  // Collected first, then stopped: a bin that stops may remove pads and
  // children, which would resync an iterator still walking it.
  std::vector<GstElement*> running;
  GstIterator* it = gst_bin_iterate_recurse(GST_BIN(pipeline));
  GValue item = G_VALUE_INIT;
  for (bool done = false; !done;) {
    switch (gst_iterator_next(it, &item)) {
      case GST_ITERATOR_OK: {
        auto* element = GST_ELEMENT(g_value_get_object(&item));
        GST_OBJECT_LOCK(element);
        const bool up = GST_STATE(element) != GST_STATE_NULL;
        GST_OBJECT_UNLOCK(element);
        if (up) running.push_back(GST_ELEMENT(gst_object_ref(element)));
        g_value_reset(&item);
        break;
      }
      case GST_ITERATOR_RESYNC:
        for (GstElement* e : running) gst_object_unref(e);
        running.clear();
        gst_iterator_resync(it);
        break;
      default:  // done, or an error: what was found is stopped all the same
        done = true;
    }
  }
  g_value_unset(&item);
  gst_iterator_free(it);
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
