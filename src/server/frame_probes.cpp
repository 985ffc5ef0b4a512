// SPDX-License-Identifier: LGPL-2.1-or-later
#include "frame_probes.hpp"

#include "caustic/gst/causticsrc.hpp"
#include "caustic/gst/frame_meta.hpp"

#include <gst/rtp/rtp.h>
#include <gst/video/video.h>

#include <map>
#include <memory>
#include <mutex>

namespace caustic::server {
namespace {

// Encoders re-time their output (x264enc shifts PTS by 1000 h and its
// segment with it); the running time is what stays the same for a frame.
GstClockTime running_time(GstPad* pad, GstBuffer* buffer) {
  GstEvent* event = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0);
  if (!event) return GST_BUFFER_PTS(buffer);
  const GstSegment* segment = nullptr;
  gst_event_parse_segment(event, &segment);
  const GstClockTime t = gst_segment_to_running_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
  gst_event_unref(event);
  return t;
}

// Keeps the newest few entries: frames that never come out (dropped by an
// encoder) must not make the table grow.
template <typename Value>
void remember(std::map<GstClockTime, Value>& table, GstClockTime key, Value value) {
  if (table.size() > 64) table.erase(table.begin());
  table[key] = value;
}

}  // namespace

void install_frame_probes(GstElement* pipeline, Metrics* metrics, FrameTold tell) {
  // Encode time: when a raw frame enters the encoder, and when it leaves.
  struct EncodeClock {
    std::mutex lock;
    std::map<GstClockTime, gint64> entered;           // running time -> monotonic time
    std::map<GstClockTime, FrameFacts> versions;  // running time -> what the frame shows
    Metrics* metrics;
  };
  auto clock = std::make_shared<EncodeClock>();
  clock->metrics = metrics;
  using ClockRef = std::shared_ptr<EncodeClock>;
  auto free_ref = [](gpointer d) { delete static_cast<ClockRef*>(d); };
  GstElement* encoder = gst_bin_get_by_name(GST_BIN(pipeline), "encoder");
  GstPad* in = gst_element_get_static_pad(encoder, "sink");
  GstPad* out = gst_element_get_static_pad(encoder, "src");
  gst_pad_add_probe(
      in, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad* pad, GstPadProbeInfo* info, gpointer data) {
        EncodeClock& c = **static_cast<ClockRef*>(data);
        GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
        std::lock_guard lock(c.lock);
        remember(c.entered, running_time(pad, buffer), g_get_monotonic_time());
        return GST_PAD_PROBE_OK;
      },
      new ClockRef(clock), free_ref);
  gst_pad_add_probe(
      out, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad* pad, GstPadProbeInfo* info, gpointer data) {
        EncodeClock& c = **static_cast<ClockRef*>(data);
        ++c.metrics->frames_sent;
        const GstClockTime when = running_time(pad, GST_PAD_PROBE_INFO_BUFFER(info));
        std::lock_guard lock(c.lock);
        auto it = c.entered.find(when);
        if (it != c.entered.end()) {
          c.metrics->encode_ms.observe((g_get_monotonic_time() - it->second) / 1000.0);
          c.entered.erase(it);
        }
        return GST_PAD_PROBE_OK;
      },
      new ClockRef(clock), free_ref);
  gst_object_unref(in);
  gst_object_unref(out);
  gst_object_unref(encoder);

  // Tell the viewer which parameter version each RTP timestamp shows.
  struct FrameTeller {
    ClockRef clock;
    FrameTold tell;
    guint32 last_timestamp = 0;
    bool any = false;
  };
  GstElement* pay = gst_bin_get_by_name(GST_BIN(pipeline), "pay");
  // The encoders carry CausticFrameMeta over to their output (it has no
  // tags); the version is read there and matched by running time on the
  // payloader's output.
  GstPad* encoded = gst_element_get_static_pad(pay, "sink");
  gst_pad_add_probe(
      encoded, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad* pad, GstPadProbeInfo* info, gpointer data) {
        EncodeClock& c = **static_cast<ClockRef*>(data);
        GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
        if (auto* meta = caustic_buffer_get_frame_meta(buffer)) {
          std::lock_guard lock(c.lock);
          remember(c.versions, running_time(pad, buffer), FrameFacts{meta->version, meta->level, meta->water_step});
        }
        return GST_PAD_PROBE_OK;
      },
      new ClockRef(clock), free_ref);
  gst_object_unref(encoded);
  GstPad* rtp = gst_element_get_static_pad(pay, "src");
  gst_pad_add_probe(
      rtp, static_cast<GstPadProbeType>(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST),
      [](GstPad* pad, GstPadProbeInfo* info, gpointer data) {
        auto* t = static_cast<FrameTeller*>(data);
        GstBuffer* buffer = (info->type & GST_PAD_PROBE_TYPE_BUFFER_LIST)
                                ? gst_buffer_list_get(GST_PAD_PROBE_INFO_BUFFER_LIST(info), 0)
                                : GST_PAD_PROBE_INFO_BUFFER(info);
        GstRTPBuffer rtp_buffer = GST_RTP_BUFFER_INIT;
        if (!buffer || !gst_rtp_buffer_map(buffer, GST_MAP_READ, &rtp_buffer)) return GST_PAD_PROBE_OK;
        const guint32 timestamp = gst_rtp_buffer_get_timestamp(&rtp_buffer);
        gst_rtp_buffer_unmap(&rtp_buffer);
        if (t->any && timestamp == t->last_timestamp) return GST_PAD_PROBE_OK;
        t->any = true;
        t->last_timestamp = timestamp;
        FrameFacts frame;
        {
          std::lock_guard lock(t->clock->lock);
          auto it = t->clock->versions.find(running_time(pad, buffer));
          if (it == t->clock->versions.end()) return GST_PAD_PROBE_OK;
          frame = it->second;
        }
        t->tell(timestamp, frame);
        return GST_PAD_PROBE_OK;
      },
      new FrameTeller{clock, std::move(tell)}, [](gpointer d) { delete static_cast<FrameTeller*>(d); });
  gst_object_unref(rtp);
  gst_object_unref(pay);
}

void pass_key_unit_requests(GstElement* pipeline) {
  GstElement* encoder = gst_bin_get_by_name(GST_BIN(pipeline), "encoder");
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
  GstPad* out = gst_element_get_static_pad(encoder, "src");
  // The probe holds a weak pointer: the pipeline owns both elements.
  gst_pad_add_probe(
      out, GST_PAD_PROBE_TYPE_EVENT_UPSTREAM,
      [](GstPad*, GstPadProbeInfo* info, gpointer data) {
        if (gst_video_event_is_force_key_unit(GST_PAD_PROBE_INFO_EVENT(info)))
          if (auto* src = static_cast<GstElement*>(g_weak_ref_get(static_cast<GWeakRef*>(data)))) {
            caustic::gst::send_next_frame(src);
            gst_object_unref(src);
          }
        return GST_PAD_PROBE_OK;
      },
      [src] {
        auto* ref = new GWeakRef;
        g_weak_ref_init(ref, src);
        return ref;
      }(),
      [](gpointer data) {
        g_weak_ref_clear(static_cast<GWeakRef*>(data));
        delete static_cast<GWeakRef*>(data);
      });
  gst_object_unref(out);
  gst_object_unref(src);
  gst_object_unref(encoder);
}

}  // namespace caustic::server
