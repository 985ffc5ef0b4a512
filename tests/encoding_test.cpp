// SPDX-License-Identifier: LGPL-2.1-or-later
// The pipeline files as the server uses them: each codec's RTP stream,
// depayloaded and decoded again, matches the raw render (PSNR bound).
#include "caustic/gst/causticsrc.hpp"
#include "caustic/server/data_files.hpp"

#include <gst/app/gstappsink.h>
#include <gst/gst.h>
#include <gst/video/video.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <vector>

namespace {

std::vector<guint8> nth_frame(const std::string& description, int n) {
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(description.c_str(), &error);
  EXPECT_EQ(error, nullptr) << (error ? error->message : "") << "\n" << description;
  if (!pipeline) return {};
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  std::vector<guint8> pixels;
  for (int i = 0; i <= n; ++i) {
    GstSample* sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 20 * GST_SECOND);
    if (!sample) {
      ADD_FAILURE() << "no frame " << i << " from\n" << description;
      break;
    }
    if (i == n) {
      GstMapInfo map;
      GstBuffer* buffer = gst_sample_get_buffer(sample);
      gst_buffer_map(buffer, &map, GST_MAP_READ);
      pixels.assign(map.data, map.data + map.size);
      gst_buffer_unmap(buffer, &map);
    }
    gst_sample_unref(sample);
  }
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
  return pixels;
}

// Values for a pipeline template: a square picture at 30 fps.
std::map<std::string, std::string> template_values(int size, int kbps, int keyframe_interval) {
  return {{"width", std::to_string(size)},           {"height", std::to_string(size)},
          {"framerate", "30"},                       {"bitrate_bps", std::to_string(kbps * 1000)},
          {"bitrate_kbps", std::to_string(kbps)},    {"keyframe_interval", std::to_string(keyframe_interval)},
          {"h264_level", "3.1"}};
}

// PSNR over the RGB channels of two RGBA images.
double psnr(const std::vector<guint8>& a, const std::vector<guint8>& b) {
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;
    const double d = double(a[i]) - double(b[i]);
    sum += d * d;
    ++count;
  }
  return 10 * std::log10(255.0 * 255.0 / (sum / count + 1e-12));
}

class Encoding : public ::testing::TestWithParam<const char*> {
 protected:
  static void SetUpTestSuite() {
    gst_init(nullptr, nullptr);
    caustic::gst::register_elements();
  }
};

}  // namespace

TEST_P(Encoding, RtpStreamDecodesToTheRawRender) {
  const std::string codec = GetParam();
  const std::string scene = std::string(CAUSTIC_DATA_DIR) + "/assets/scenes/wavy.json";
  const auto values = template_values(256, 4000, 30);
  std::string sender = caustic::server::pipeline_description(CAUSTIC_DATA_DIR, codec, values);
  sender.replace(sender.find("causticsrc name=src"), 19, "causticsrc name=src scene=" + scene);
  const std::string decoder = codec == "vp8" ? "rtpvp8depay ! vp8dec" : "rtph264depay ! h264parse ! avdec_h264";
  const auto decoded = nth_frame(sender + " ! " + decoder + " ! videoconvert ! video/x-raw,format=RGBA ! appsink name=sink", 10);
  const auto raw = nth_frame("causticsrc name=src scene=" + scene + " width=256 height=256 ! appsink name=sink", 0);
  ASSERT_EQ(decoded.size(), 256u * 256u * 4u);
  ASSERT_EQ(raw.size(), decoded.size());
  const double db = psnr(decoded, raw);
  std::printf("%s: PSNR %.1f dB at 4 Mbit/s, 256x256\n", codec.c_str(), db);
  EXPECT_GT(db, 30.0);
}


TEST(PipelineTemplate, RejectsUnknownCodecsAndInjectedValues) {
  const auto values = template_values(256, 4000, 30);
  EXPECT_THROW(caustic::server::pipeline_description(CAUSTIC_DATA_DIR, "av1", values), std::runtime_error);
  EXPECT_THROW(caustic::server::pipeline_description(CAUSTIC_DATA_DIR, "../vp8", values), std::runtime_error);
  auto injected = values;
  injected["width"] = "256 ! filesink location=/tmp/x";
  EXPECT_THROW(caustic::server::pipeline_description(CAUSTIC_DATA_DIR, "vp8", injected), std::runtime_error);
  auto missing = values;
  missing.erase("bitrate_bps");
  EXPECT_THROW(caustic::server::pipeline_description(CAUSTIC_DATA_DIR, "vp8", missing), std::runtime_error);
}

TEST_P(Encoding, UpstreamKeyUnitRequestGetsAKeyFrame) {
  // What webrtcbin sends upstream when a viewer reports loss (PLI/FIR).
  const std::string codec = GetParam();
  const std::string scene = std::string(CAUSTIC_DATA_DIR) + "/assets/scenes/slab.json";
  const auto values = template_values(128, 1000, 100000);  // no unrequested key frames
  std::string sender = caustic::server::pipeline_description(CAUSTIC_DATA_DIR, codec, values);
  sender.replace(sender.find("causticsrc name=src"), 19, "causticsrc name=src scene=" + scene);
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch((sender + " ! appsink name=sink").c_str(), &error);
  ASSERT_EQ(error, nullptr);
  GstElement* encoder = gst_bin_get_by_name(GST_BIN(pipeline), "encoder");
  GstPad* encoded = gst_element_get_static_pad(encoder, "src");
  std::atomic<int> frames{0}, key_frames{0};
  struct Counts {
    std::atomic<int>* frames;
    std::atomic<int>* keys;
  } counts{&frames, &key_frames};
  gst_pad_add_probe(
      encoded, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo* info, gpointer data) {
        auto* c = static_cast<Counts*>(data);
        ++*c->frames;
        if (!GST_BUFFER_FLAG_IS_SET(GST_PAD_PROBE_INFO_BUFFER(info), GST_BUFFER_FLAG_DELTA_UNIT)) ++*c->keys;
        return GST_PAD_PROBE_OK;
      },
      &counts, nullptr);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  auto pull_frames = [&](int n) {
    const int target = frames + n;
    for (int i = 0; i < 2000 && frames < target; ++i)
      if (GstSample* s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), GST_SECOND / 10)) gst_sample_unref(s);
  };
  pull_frames(10);
  const int keys_before = key_frames;
  EXPECT_EQ(keys_before, 1) << "only the first frame should be a key frame";
  GstPad* sink_pad = gst_element_get_static_pad(sink, "sink");
  gst_pad_push_event(sink_pad, gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
  pull_frames(5);
  EXPECT_GT(key_frames.load(), keys_before) << codec << " ignored the key unit request";
  gst_object_unref(sink_pad);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(encoded);
  gst_object_unref(encoder);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
}

INSTANTIATE_TEST_SUITE_P(Codecs, Encoding, ::testing::Values("vp8", "h264"));
