// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/gst/bin_elements.hpp"

namespace caustic::gst {

std::vector<GstElement*> bin_elements(GstElement* bin, bool recurse, const std::function<bool(GstElement*)>& keep) {
  std::vector<GstElement*> found;
  if (!bin || !GST_IS_BIN(bin)) return found;
  GstIterator* it = recurse ? gst_bin_iterate_recurse(GST_BIN(bin)) : gst_bin_iterate_elements(GST_BIN(bin));
  GValue item = G_VALUE_INIT;
  for (bool done = false; !done;) {
    switch (gst_iterator_next(it, &item)) {
      case GST_ITERATOR_OK: {
        auto* element = GST_ELEMENT(g_value_get_object(&item));
        if (keep(element)) found.push_back(GST_ELEMENT(gst_object_ref(element)));
        g_value_reset(&item);
        break;
      }
      case GST_ITERATOR_RESYNC:
        for (GstElement* e : found) gst_object_unref(e);
        found.clear();
        gst_iterator_resync(it);
        break;
      default:  // done, or an error
        done = true;
    }
  }
  g_value_unset(&item);
  gst_iterator_free(it);
  return found;
}

}  // namespace caustic::gst
