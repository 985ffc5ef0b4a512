// SPDX-License-Identifier: LGPL-2.1-or-later
// release_receive_bins (src/server/receive_bins.hpp) against webrtcbin
// 1.22's own receive bin: a state change of its ICE transport after the
// pipeline stopped makes a pad block that holds the bin, and the bin (with
// its nicesrc, the ICE agent and the agent's sockets) then outlives the
// pipeline. The oracle is the bin's finalization (a weak reference), not
// anything the function says of itself.
#include "ice_setup.hpp"
#include "receive_bins.hpp"

#include <gtest/gtest.h>
#include <gst/gst.h>

#include <cstring>

namespace {

struct Webrtc {
  GstElement* pipeline = nullptr;
  GstElement* webrtcbin = nullptr;
  GstElement* receive_bin = nullptr;  // borrowed: a child of webrtcbin
  GObject* ice_transport = nullptr;   // owned
  bool receive_bin_gone = false;

  Webrtc() {
    gst_init(nullptr, nullptr);
    GError* error = nullptr;
    pipeline = gst_parse_launch(
        "videotestsrc is-live=true ! video/x-raw,width=64,height=64 ! vp8enc deadline=1 ! rtpvp8pay ! "
        "application/x-rtp,media=video,encoding-name=VP8,payload=96 ! webrtcbin name=w bundle-policy=max-bundle",
        &error);
    EXPECT_EQ(error, nullptr);
    webrtcbin = gst_bin_get_by_name(GST_BIN(pipeline), "w");
    caustic::server::ServerConfig config;
    config.ice_addresses = {"127.0.0.1"};  // ICE stays on loopback
    EXPECT_TRUE(caustic::server::configure_ice(webrtcbin, config).empty());
  }
  ~Webrtc() {
    if (ice_transport) g_object_unref(ice_transport);
    if (webrtcbin) gst_object_unref(webrtcbin);
    if (pipeline) {
      gst_element_set_state(pipeline, GST_STATE_NULL);
      gst_object_unref(pipeline);
    }
  }

  // Streams, makes an offer with a data channel (as a session does) and
  // applies it: that makes the transport, its receive bin, and gathers.
  void offer() {
    ASSERT_NE(gst_element_set_state(pipeline, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
    GObject* channel = nullptr;
    g_signal_emit_by_name(webrtcbin, "create-data-channel", "frames", nullptr, &channel);
    ASSERT_NE(channel, nullptr);
    g_object_unref(channel);
    GstPromise* made = gst_promise_new();
    g_signal_emit_by_name(webrtcbin, "create-offer", nullptr, made);
    ASSERT_EQ(gst_promise_wait(made), GST_PROMISE_RESULT_REPLIED);
    GstStructure* offer_holder = gst_structure_copy(gst_promise_get_reply(made));
    gst_promise_unref(made);
    GValue offer = G_VALUE_INIT;
    ASSERT_TRUE(gst_structure_has_field(offer_holder, "offer"));
    g_value_copy(gst_structure_get_value(offer_holder, "offer"), g_value_init(&offer, G_VALUE_TYPE(gst_structure_get_value(offer_holder, "offer"))));
    GstPromise* applied = gst_promise_new();
    g_signal_emit_by_name(webrtcbin, "set-local-description", g_value_get_boxed(&offer), applied);
    ASSERT_EQ(gst_promise_wait(applied), GST_PROMISE_RESULT_REPLIED);
    gst_promise_unref(applied);
    g_value_unset(&offer);
    gst_structure_free(offer_holder);

    GstIterator* it = gst_bin_iterate_elements(GST_BIN(webrtcbin));
    GValue item = G_VALUE_INIT;
    while (gst_iterator_next(it, &item) == GST_ITERATOR_OK) {
      auto* e = GST_ELEMENT(g_value_get_object(&item));
      if (std::strcmp(G_OBJECT_TYPE_NAME(e), "TransportReceiveBin") == 0) receive_bin = e;
      g_value_reset(&item);
    }
    g_value_unset(&item);
    gst_iterator_free(it);
    ASSERT_NE(receive_bin, nullptr) << "webrtcbin made no receive bin for its offer";
    g_object_weak_ref(G_OBJECT(receive_bin), [](gpointer gone, GObject*) { *static_cast<bool*>(gone) = true; },
                      &receive_bin_gone);

    GObject* sctp = nullptr;
    g_object_get(webrtcbin, "sctp-transport", &sctp, nullptr);
    ASSERT_NE(sctp, nullptr);
    GObject* dtls = nullptr;
    g_object_get(sctp, "transport", &dtls, nullptr);
    g_object_unref(sctp);
    ASSERT_NE(dtls, nullptr);
    g_object_get(dtls, "transport", &ice_transport, nullptr);
    g_object_unref(dtls);
    ASSERT_NE(ice_transport, nullptr);
  }

  // What gathering that starts late does: the ICE transport's state
  // changes (here: is said to) while the receive bin is down.
  void ice_state_changes() { g_object_notify(ice_transport, "state"); }

  // Drops the pipeline as a session does; whether the receive bin went too.
  bool everything_freed() {
    gst_object_unref(webrtcbin);
    webrtcbin = nullptr;
    gst_object_unref(pipeline);
    pipeline = nullptr;
    return receive_bin_gone;
  }
};

bool blocked_inside(GstElement* bin) {
  bool blocked = false;
  GstIterator* it = gst_bin_iterate_recurse(GST_BIN(bin));
  GValue item = G_VALUE_INIT;
  while (gst_iterator_next(it, &item) == GST_ITERATOR_OK) {
    GstPad* src = gst_element_get_static_pad(GST_ELEMENT(g_value_get_object(&item)), "src");
    if (src) blocked = blocked || gst_pad_is_blocked(src);
    if (src) gst_object_unref(src);
    g_value_reset(&item);
  }
  g_value_unset(&item);
  gst_iterator_free(it);
  return blocked;
}

}  // namespace

TEST(ReceiveBins, AnOrdinaryStopFreesTheReceiveBinAndReleasesNothing) {
  Webrtc w;
  ASSERT_NO_FATAL_FAILURE(w.offer());
  gst_element_set_state(w.pipeline, GST_STATE_NULL);
  EXPECT_EQ(caustic::server::release_receive_bins(w.webrtcbin), 0);
  EXPECT_TRUE(w.everything_freed());
}

TEST(ReceiveBins, AnIceStateChangeAfterTheStopKeepsTheBinUnlessReleased) {
  // First the defect itself, so that the test below cannot pass by chance:
  // nothing done, the bin holds itself and outlives its pipeline.
  {
    Webrtc w;
    ASSERT_NO_FATAL_FAILURE(w.offer());
    gst_element_set_state(w.pipeline, GST_STATE_NULL);
    w.ice_state_changes();
    ASSERT_TRUE(blocked_inside(w.receive_bin)) << "webrtcbin no longer re-blocks a stopped receive bin";
    EXPECT_FALSE(w.everything_freed()) << "webrtcbin no longer keeps a re-blocked receive bin";
  }
  // Released: the block goes and the bin is freed with its pipeline.
  Webrtc w;
  ASSERT_NO_FATAL_FAILURE(w.offer());
  gst_element_set_state(w.pipeline, GST_STATE_NULL);
  w.ice_state_changes();
  EXPECT_EQ(caustic::server::release_receive_bins(w.webrtcbin), 1);
  EXPECT_FALSE(blocked_inside(w.receive_bin));
  EXPECT_TRUE(w.everything_freed());
}

TEST(ReceiveBins, AStateChangeAfterTheReleaseMakesNoBlock) {
  Webrtc w;
  ASSERT_NO_FATAL_FAILURE(w.offer());
  gst_element_set_state(w.pipeline, GST_STATE_NULL);
  EXPECT_EQ(caustic::server::release_receive_bins(w.webrtcbin), 0);
  w.ice_state_changes();  // the handler is gone: no block
  EXPECT_FALSE(blocked_inside(w.receive_bin));
  EXPECT_TRUE(w.everything_freed());
}

TEST(ReceiveBins, TakesAnElementThatIsNoWebrtcbin) {
  gst_init(nullptr, nullptr);
  GstElement* alone = gst_element_factory_make("fakesrc", nullptr);
  ASSERT_NE(alone, nullptr);
  EXPECT_EQ(caustic::server::release_receive_bins(alone), 0);
  gst_object_unref(alone);
  EXPECT_EQ(caustic::server::release_receive_bins(nullptr), 0);
}
