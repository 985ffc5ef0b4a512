// SPDX-License-Identifier: LGPL-2.1-or-later
// causticsrc's properties across its states: they change in NULL or READY
// only (the streaming and render threads read them without a lock), and a
// scene file set between two runs is the one the next run shows.
#include "causticsrc_fixture.hpp"

#include <gst/gst.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace caustic::testing;

TEST_F(CausticSrc, APropertySetWhileStreamingIsKeptAsItWas) {
  start("causticsrc name=src scene=" + scene("slab") + " width=32 height=32 settle-ms=40 ! appsink name=sink");
  gst_sample_unref(pull());
  g_object_set(src_, "settle-ms", 500u, "still-interval-ms", 300u, nullptr);
  guint settle = 0, still = 0;
  g_object_get(src_, "settle-ms", &settle, "still-interval-ms", &still, nullptr);
  EXPECT_EQ(settle, 40u);
  EXPECT_EQ(still, 0u);
  // Back in READY, the same writes take.
  ASSERT_NE(gst_element_set_state(pipeline_.get(), GST_STATE_READY), GST_STATE_CHANGE_FAILURE);
  ASSERT_EQ(gst_element_get_state(pipeline_.get(), nullptr, nullptr, 10 * GST_SECOND), GST_STATE_CHANGE_SUCCESS);
  g_object_set(src_, "settle-ms", 500u, "still-interval-ms", 300u, nullptr);
  g_object_get(src_, "settle-ms", &settle, "still-interval-ms", &still, nullptr);
  EXPECT_EQ(settle, 500u);
  EXPECT_EQ(still, 300u);
}

TEST_F(CausticSrc, ASceneSetBetweenTwoRunsIsTheOneTheNextRunShows) {
  // The slab's screen stands 50 mm from it, the lens's 80 mm (their files).
  start("causticsrc name=src scene=" + scene("slab") + " width=32 height=32 ! appsink name=sink");
  gst_sample_unref(pull());
  ASSERT_EQ(caustic::gst::param_store(src_)->snapshot().scene.focus_distance, 50.0);
  ASSERT_NE(gst_element_set_state(pipeline_.get(), GST_STATE_NULL), GST_STATE_CHANGE_FAILURE);
  g_object_set(src_, "scene", scene("lens").c_str(), nullptr);
  ASSERT_NE(gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  GstSample* sample = pull();
  ASSERT_NE(sample, nullptr);
  gst_sample_unref(sample);
  EXPECT_EQ(caustic::gst::param_store(src_)->snapshot().scene.focus_distance, 80.0);
  // The same file again keeps the store, and with it the changes made to it.
  ASSERT_NE(gst_element_set_state(pipeline_.get(), GST_STATE_NULL), GST_STATE_CHANGE_FAILURE);
  const auto before = caustic::gst::param_store(src_);
  g_object_set(src_, "scene", scene("lens").c_str(), nullptr);
  ASSERT_NE(gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  sample = pull();
  ASSERT_NE(sample, nullptr);
  gst_sample_unref(sample);
  EXPECT_EQ(caustic::gst::param_store(src_), before);
}

TEST_F(CausticSrc, ItsLatencyIsOneFrameIntervalOfTheNegotiatedRate) {
  // A frame leaves when due with a picture finished before: live, with at
  // most one interval of latency (the query may come from any thread).
  start("causticsrc name=src scene=" + scene("slab") + " width=32 height=32 framerate=25/1 ! appsink name=sink");
  gst_sample_unref(pull());
  GstQuery* query = gst_query_new_latency();
  ASSERT_TRUE(gst_element_query(src_, query));
  gboolean live = FALSE;
  GstClockTime min = 0, max = 0;
  gst_query_parse_latency(query, &live, &min, &max);
  gst_query_unref(query);
  EXPECT_TRUE(live);
  EXPECT_EQ(min, GST_SECOND / 25);
  EXPECT_EQ(max, GST_SECOND / 25);
}

}  // namespace
