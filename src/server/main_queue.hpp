// SPDX-License-Identifier: LGPL-2.1-or-later
// Work that library threads (webrtcbin's, ICE's, a gallery loader) hand to
// the main loop. g_main_context_invoke() runs it at once on the calling
// thread whenever no thread holds the context (a loop that has returned,
// the server's teardown between its iterations): the very thread it must
// not run on. queue_on() always queues; what a loop never runs again is
// freed with the context (`destroy` called, `fn` not).
#pragma once

#include <glib.h>

namespace caustic::server {

inline void queue_on(GMainContext* context, GSourceFunc fn, gpointer data, GDestroyNotify destroy) {
  GSource* source = g_idle_source_new();
  g_source_set_priority(source, G_PRIORITY_DEFAULT);
  g_source_set_callback(source, fn, data, destroy);
  g_source_attach(source, context);
  g_source_unref(source);
}

}  // namespace caustic::server
