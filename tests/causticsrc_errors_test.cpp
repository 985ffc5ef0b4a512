// SPDX-License-Identifier: LGPL-2.1-or-later
// causticsrc's failures: each ends the stream with an error on the bus
// that names its cause, rather than a stream that goes on showing nothing
// or an old picture.
#include "causticsrc_fixture.hpp"

#include "caustic/engine.hpp"

#include <gst/gst.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace {

using namespace caustic::testing;

TEST_F(CausticSrc, ARenderThatFailsAfterTheFirstPictureIsAnErrorOnTheBus) {
  // The frame observer runs inside each render on the render thread: its
  // second call fails as a lost GL context would. The stream must end with
  // the error, not send the first picture on for ever.
  std::atomic<int> calls{0};
  start("causticsrc name=src scene=" + scene("slab") + " width=32 height=32 framerate=30/1 ! appsink name=sink",
        [&](const caustic::FrameStats&, std::uint64_t) {
          if (++calls == 2) throw std::runtime_error("the context was lost");
        });
  gst_sample_unref(pull());
  caustic::gst::param_store(src_)->apply_patch({{"light", {{"direction", {0.05, 0.0, -1.0}}}}});
  GstBus* bus = gst_element_get_bus(pipeline_.get());
  GstMessage* msg = gst_bus_timed_pop_filtered(bus, 20 * GST_SECOND, GST_MESSAGE_ERROR);
  ASSERT_NE(msg, nullptr) << "no error on the bus; the render observer ran " << calls.load() << " times";
  GError* err = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(msg, &err, &debug);
  EXPECT_NE(std::string(debug ? debug : "").find("the context was lost"), std::string::npos) << debug;
  g_error_free(err);
  g_free(debug);
  gst_message_unref(msg);
  gst_object_unref(bus);
}

TEST_F(CausticSrc, MissingSceneIsAnErrorOnTheBus) {
  GError* error = nullptr;
  pipeline_.reset(gst_parse_launch("causticsrc scene=/nonexistent.json ! fakesink", &error));
  ASSERT_EQ(error, nullptr);
  EXPECT_EQ(gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  GstBus* bus = gst_element_get_bus(pipeline_.get());
  GstMessage* msg = gst_bus_timed_pop_filtered(bus, GST_SECOND, GST_MESSAGE_ERROR);
  ASSERT_NE(msg, nullptr);
  GError* err = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(msg, &err, &debug);
  EXPECT_NE(std::string(debug).find("nonexistent"), std::string::npos) << debug;
  g_error_free(err);
  g_free(debug);
  gst_message_unref(msg);
  gst_object_unref(bus);
}

}  // namespace
