// SPDX-License-Identifier: LGPL-2.1-or-later
// stop_pipeline (src/gst/stop_pipeline.hpp) against what a pipeline's own
// set_state(NULL) leaves running: an element up inside a stopped pipeline,
// locked in its state as webrtcbin's receive bin locks its nicesrc, is
// skipped by its bins' state changes, and only the sweep stops it.
#include "caustic/gst/stop_pipeline.hpp"

#include <gtest/gtest.h>

namespace {

GstState state_of(GstElement* e) {
  GstState state = GST_STATE_VOID_PENDING;
  gst_element_get_state(e, &state, nullptr, GST_CLOCK_TIME_NONE);
  return state;
}

// A source two bins down, as a nicesrc sits inside webrtcbin's transport bin.
struct Pipeline {
  GstElement* top = nullptr;
  GstElement* inner = nullptr;
  Pipeline() {
    gst_init(nullptr, nullptr);
    GError* error = nullptr;
    top = gst_parse_launch("bin name=outer ( bin name=middle ( fakesrc name=inner ! fakesink ) )", &error);
    EXPECT_EQ(error, nullptr);
    inner = gst_bin_get_by_name(GST_BIN(top), "inner");
  }
  ~Pipeline() {
    gst_element_set_locked_state(inner, FALSE);
    gst_element_set_state(inner, GST_STATE_NULL);
    gst_element_set_state(top, GST_STATE_NULL);
    gst_object_unref(inner);
    gst_object_unref(top);
  }
};

}  // namespace

TEST(StopPipeline, AnOrdinaryStopLeavesNothingBehind) {
  Pipeline p;
  ASSERT_NE(gst_element_set_state(p.top, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  EXPECT_EQ(caustic::gst::stop_pipeline(p.top), 0);
  EXPECT_EQ(state_of(p.top), GST_STATE_NULL);
  EXPECT_EQ(state_of(p.inner), GST_STATE_NULL);
}

TEST(StopPipeline, StopsALockedElementLeftRunningInsideAStoppedPipeline) {
  Pipeline p;
  ASSERT_NE(gst_element_set_state(p.top, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  gst_element_set_state(p.top, GST_STATE_NULL);
  // The straggler: locked, up again while everything round it is NULL.
  gst_element_set_locked_state(p.inner, TRUE);
  ASSERT_NE(gst_element_set_state(p.inner, GST_STATE_PAUSED), GST_STATE_CHANGE_FAILURE);
  // The pipeline's own stop passes it by.
  gst_element_set_state(p.top, GST_STATE_NULL);
  ASSERT_EQ(state_of(p.inner), GST_STATE_PAUSED);

  EXPECT_EQ(caustic::gst::stop_pipeline(p.top), 1);
  EXPECT_EQ(state_of(p.inner), GST_STATE_NULL);
}

TEST(StopPipeline, TakesNoPipelineAndALoneElement) {
  EXPECT_EQ(caustic::gst::stop_pipeline(nullptr), 0);
  gst_init(nullptr, nullptr);
  GstElement* alone = gst_element_factory_make("fakesrc", nullptr);
  ASSERT_NE(alone, nullptr);
  gst_element_set_state(alone, GST_STATE_PAUSED);
  EXPECT_EQ(caustic::gst::stop_pipeline(alone), 0);
  EXPECT_EQ(state_of(alone), GST_STATE_NULL);
  gst_object_unref(alone);
}
