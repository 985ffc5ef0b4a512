// SPDX-License-Identifier: LGPL-2.1-or-later
// What the causticsrc tests share: a pipeline from a launch line with the
// element named "src" and an appsink named "sink", and the frames it takes.
#pragma once

#include "caustic/gst/causticsrc.hpp"
#include "caustic/gst/frame_meta.hpp"

#include <gst/app/gstappsink.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace caustic::testing {

using PipelinePtr = std::unique_ptr<GstElement, void (*)(GstElement*)>;

inline void stop_and_unref(GstElement* pipeline) {
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
}

class CausticSrc : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    gst_init(nullptr, nullptr);
    ASSERT_TRUE(caustic::gst::register_elements());
  }

  // `observer`, when given, is set before the render thread starts.
  void start(const std::string& description, caustic::gst::FrameObserver observer = {}) {
    GError* error = nullptr;
    pipeline_.reset(gst_parse_launch(description.c_str(), &error));
    ASSERT_EQ(error, nullptr) << error->message;
    src_ = gst_bin_get_by_name(GST_BIN(pipeline_.get()), "src");
    sink_ = gst_bin_get_by_name(GST_BIN(pipeline_.get()), "sink");
    if (observer) caustic::gst::set_frame_observer(src_, std::move(observer));
    ASSERT_NE(gst_element_set_state(pipeline_.get(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  }
  void TearDown() override {
    if (src_) gst_object_unref(src_);
    if (sink_) gst_object_unref(sink_);
  }

  // The next sample, or null after 10 s.
  GstSample* pull() { return gst_app_sink_try_pull_sample(GST_APP_SINK(sink_), 10 * GST_SECOND); }

  // The pipeline's running time now (what a frame's timestamp counts);
  // GST_CLOCK_TIME_NONE before it has a clock.
  GstClockTime running_time() {
    GstClock* clock = gst_element_get_clock(pipeline_.get());
    if (!clock) return GST_CLOCK_TIME_NONE;
    const GstClockTime now = gst_clock_get_time(clock) - gst_element_get_base_time(pipeline_.get());
    gst_object_unref(clock);
    return now;
  }

  std::uint64_t renders() {
    guint64 n = 0;
    g_object_get(src_, "renders", &n, nullptr);
    return n;
  }

  PipelinePtr pipeline_{nullptr, stop_and_unref};
  GstElement* src_ = nullptr;
  GstElement* sink_ = nullptr;
};

inline std::string scene(const char* name) { return std::string(CAUSTIC_ASSET_DIR) + "/scenes/" + name + ".json"; }

struct Frame {
  GstClockTime pts;
  std::uint64_t version;
  std::uint32_t level;
  std::uint64_t water_step;
  std::vector<guint8> pixels;
  int width, height;
};

inline Frame take(GstSample* sample) {
  Frame f{};
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  const GstStructure* st = gst_caps_get_structure(gst_sample_get_caps(sample), 0);
  gst_structure_get_int(st, "width", &f.width);
  gst_structure_get_int(st, "height", &f.height);
  f.pts = GST_BUFFER_PTS(buffer);
  auto* meta = caustic_buffer_get_frame_meta(buffer);
  f.version = meta ? meta->version : 0;
  f.level = meta ? meta->level : 99;
  f.water_step = meta ? meta->water_step : 0;
  GstMapInfo map;
  gst_buffer_map(buffer, &map, GST_MAP_READ);
  f.pixels.assign(map.data, map.data + map.size);
  gst_buffer_unmap(buffer, &map);
  gst_sample_unref(sample);
  return f;
}

}  // namespace caustic::testing
