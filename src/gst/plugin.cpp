// SPDX-License-Identifier: LGPL-2.1-or-later
// The plugin file libgstcaustic.so: causticsrc for gst-launch-1.0,
// gst-inspect-1.0 and any GStreamer application. causticd links the same
// element in and registers it as a static plugin (register_elements()).
#include "caustic/gst/causticsrc.hpp"

#define PACKAGE "causticd"

static gboolean plugin_init(GstPlugin* plugin) { return caustic::gst::register_element(plugin) ? TRUE : FALSE; }

GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, caustic, "Caustic rendering", plugin_init, CAUSTICD_VERSION,
                  "LGPL", "causticd", "https://localhost.localdomain/causticd")
