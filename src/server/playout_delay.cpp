// SPDX-License-Identifier: LGPL-2.1-or-later
// GObject boilerplate for one GstRTPHeaderExtension: the work is write(),
// three zero bytes.
#include "playout_delay.hpp"

#include <gst/rtp/rtp.h>

namespace caustic::server {
namespace {

// The extension's data: a 12-bit minimum and a 12-bit maximum (10 ms units).
constexpr gsize kSize = 3;

struct CausticPlayoutDelay {
  GstRTPHeaderExtension parent;
};
struct CausticPlayoutDelayClass {
  GstRTPHeaderExtensionClass parent_class;
};

G_DEFINE_TYPE(CausticPlayoutDelay, caustic_playout_delay, GST_TYPE_RTP_HEADER_EXTENSION)

GstRTPHeaderExtensionFlags supported_flags(GstRTPHeaderExtension*) {
  return static_cast<GstRTPHeaderExtensionFlags>(GST_RTP_HEADER_EXTENSION_ONE_BYTE |
                                                 GST_RTP_HEADER_EXTENSION_TWO_BYTE);
}

gsize max_size(GstRTPHeaderExtension*, const GstBuffer*) { return kSize; }

// Every packet carries it: a receiver joining late, or one that lost the
// first packets, reads it from whichever frame comes.
gssize write(GstRTPHeaderExtension*, const GstBuffer*, GstRTPHeaderExtensionFlags, GstBuffer*, guint8* data,
             gsize size) {
  if (size < kSize) return -1;
  data[0] = data[1] = data[2] = 0;  // minimum 0, maximum 0
  return kSize;
}

// Only sent; what a peer might send back is not acted on.
gboolean read(GstRTPHeaderExtension*, GstRTPHeaderExtensionFlags, const guint8*, gsize size, GstBuffer*) {
  return size >= kSize;
}

void caustic_playout_delay_class_init(CausticPlayoutDelayClass* klass) {
  auto* ext = GST_RTP_HEADER_EXTENSION_CLASS(klass);
  ext->get_supported_flags = supported_flags;
  ext->get_max_size = max_size;
  ext->write = write;
  ext->read = read;
  gst_element_class_set_static_metadata(GST_ELEMENT_CLASS(klass), "Playout delay RTP header extension",
                                        GST_RTP_HDREXT_ELEMENT_CLASS, "Asks the receiver to show frames at once",
                                        "causticd");
  gst_rtp_header_extension_class_set_uri(ext, kPlayoutDelayUri);
}

void caustic_playout_delay_init(CausticPlayoutDelay*) {}

}  // namespace

GstElement* make_playout_delay_extension(guint id) {
  auto* ext = GST_RTP_HEADER_EXTENSION(g_object_new(caustic_playout_delay_get_type(), nullptr));
  gst_rtp_header_extension_set_id(ext, id);
  return GST_ELEMENT(ext);
}

bool add_playout_delay(GstElement* pay) {
  if (!pay || !g_signal_lookup("add-extension", G_OBJECT_TYPE(pay))) return false;
  // The payloaders here carry no other extension; webrtcbin numbers its
  // own (if any) from the offer's caps, which then hold this one's.
  GstElement* ext = make_playout_delay_extension(kPlayoutDelayId);
  gst_object_ref_sink(ext);
  g_signal_emit_by_name(pay, "add-extension", ext);
  gst_object_unref(ext);
  return true;
}

}  // namespace caustic::server
