// SPDX-License-Identifier: LGPL-2.1-or-later
// causticsrc given new caps while it streams (a downstream element that
// renegotiates, as videoconvert ! autovideosink may): the worker drew on in
// the old format, so I420 caps carried RGBA bytes, and the frame grid,
// counted at the old rate, sent timestamps backwards.
#include "causticsrc_fixture.hpp"

#include <gst/video/video.h>

using namespace caustic::testing;

TEST_F(CausticSrc, NewCapsMidStreamBringBuffersOfTheirFormatAndTimestampsGoOn) {
  start("causticsrc name=src scene=" + scene("lens") +
        " width=64 height=64 ! capsfilter name=f caps=video/x-raw,format=RGBA,framerate=30/1 ! appsink name=sink");
  GstElement* filter = gst_bin_get_by_name(GST_BIN(pipeline_.get()), "f");
  ASSERT_NE(filter, nullptr);
  GstClockTime last = 0;
  int after = 0;  // buffers under the new caps
  for (int i = 0; i < 60 && after < 8; ++i) {
    if (i == 5) {
      GstCaps* caps = gst_caps_from_string("video/x-raw,format=I420,framerate=60/1");
      g_object_set(filter, "caps", caps, nullptr);
      gst_caps_unref(caps);
    }
    GstSample* sample = pull();
    ASSERT_NE(sample, nullptr) << "no frame " << i;
    GstVideoInfo info;
    ASSERT_TRUE(gst_video_info_from_caps(&info, gst_sample_get_caps(sample)));
    GstBuffer* buffer = gst_sample_get_buffer(sample);
    EXPECT_EQ(gst_buffer_get_size(buffer), GST_VIDEO_INFO_SIZE(&info))
        << "frame " << i << " under " << gst_video_format_to_string(GST_VIDEO_INFO_FORMAT(&info));
    if (i > 0) {
      EXPECT_GT(GST_BUFFER_PTS(buffer), last) << "frame " << i;
    }
    last = GST_BUFFER_PTS(buffer);
    after += GST_VIDEO_INFO_FORMAT(&info) == GST_VIDEO_FORMAT_I420;
    gst_sample_unref(sample);
  }
  EXPECT_GE(after, 8) << "the new caps never came";
  gst_object_unref(filter);
}
