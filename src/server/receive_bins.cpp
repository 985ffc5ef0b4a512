// SPDX-License-Identifier: LGPL-2.1-or-later
#include "receive_bins.hpp"

#include "caustic/gst/bin_elements.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

namespace caustic::server {
namespace {

// The receive bins' type, private to webrtcbin: known by name, reached
// through GstBin and GObject alone.
constexpr const char* kReceiveBinType = "TransportReceiveBin";

// `object`'s property `name`, an object (a new reference), or null.
GObject* object_property(gpointer object, const char* name) {
  if (!object || !g_object_class_find_property(G_OBJECT_GET_CLASS(object), name)) return nullptr;
  GObject* value = nullptr;
  g_object_get(object, name, &value, nullptr);
  return value;
}

// Every ICE transport of the webrtcbin's transceivers and data channels
// (with max-bundle, one), each a new reference.
std::vector<GObject*> ice_transports(GstElement* webrtcbin) {
  std::vector<GObject*> dtls;
  GArray* transceivers = nullptr;
  g_signal_emit_by_name(webrtcbin, "get-transceivers", &transceivers);
  for (guint i = 0; transceivers && i < transceivers->len; ++i) {
    GObject* transceiver = g_array_index(transceivers, GObject*, i);
    for (const char* side : {"sender", "receiver"}) {
      GObject* end = object_property(transceiver, side);
      if (GObject* transport = object_property(end, "transport")) dtls.push_back(transport);
      if (end) g_object_unref(end);
    }
  }
  if (transceivers) g_array_unref(transceivers);
  GObject* sctp = object_property(webrtcbin, "sctp-transport");
  if (GObject* transport = object_property(sctp, "transport")) dtls.push_back(transport);
  if (sctp) g_object_unref(sctp);

  std::vector<GObject*> ice;
  for (GObject* d : dtls) {
    GObject* transport = object_property(d, "transport");
    if (transport && std::find(ice.begin(), ice.end(), transport) == ice.end())
      ice.push_back(transport);
    else if (transport)
      g_object_unref(transport);
    g_object_unref(d);
  }
  return ice;
}

// Whether a blocking probe sits on any pad of an element inside `bin`.
bool holds_a_block(GstElement* bin) {
  const auto blocked = gst::bin_elements(bin, true, [](GstElement* element) {
    bool any = false;
    GstIterator* pads = gst_element_iterate_pads(element);
    GValue pad = G_VALUE_INIT;
    while (!any && gst_iterator_next(pads, &pad) == GST_ITERATOR_OK) {
      any = gst_pad_is_blocked(GST_PAD(g_value_get_object(&pad)));
      g_value_reset(&pad);
    }
    g_value_unset(&pad);
    gst_iterator_free(pads);
    return any;
  });
  for (GstElement* e : blocked) gst_object_unref(e);
  return !blocked.empty();
}

}  // namespace

int release_receive_bins(GstElement* webrtcbin) {
  // webrtcbin's direct children of that type.
  const std::vector<GstElement*> bins = gst::bin_elements(webrtcbin, false, [](GstElement* element) {
    return std::strcmp(G_OBJECT_TYPE_NAME(element), kReceiveBinType) == 0;
  });
  if (bins.empty()) return 0;
  std::vector<GObject*> ice = ice_transports(webrtcbin);
  // The handler's data is the bin: that matches its handler and no other.
  for (GObject* transport : ice) {
    for (GstElement* bin : bins)
      g_signal_handlers_disconnect_matched(transport, G_SIGNAL_MATCH_DATA, 0, 0, nullptr, nullptr, bin);
    g_object_unref(transport);
  }
  int released = 0;
  for (GstElement* bin : bins) {
    GST_OBJECT_LOCK(bin);
    const bool down = GST_STATE(bin) == GST_STATE_NULL;
    GST_OBJECT_UNLOCK(bin);
    if (down && holds_a_block(bin)) {
      // NULL to READY keeps the block it finds (and starts the nicesrc for a
      // moment); READY to NULL stops the nicesrc and frees the block.
      gst_element_set_state(bin, GST_STATE_READY);
      gst_element_set_state(bin, GST_STATE_NULL);
      ++released;
    }
    gst_object_unref(bin);
  }
  return released;
}

}  // namespace caustic::server
