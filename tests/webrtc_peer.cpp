// SPDX-License-Identifier: LGPL-2.1-or-later
#include "webrtc_peer.hpp"

#include "webrtc_answer.hpp"

#define GST_USE_UNSTABLE_API
#include <gst/app/gstappsink.h>
#include <gst/rtp/rtp.h>
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>

namespace caustic::testing {

WebRtcPeer::WebRtcPeer(const std::string& codec, const std::string& ws_url)
    : codec_(codec), context_(g_main_context_ref_thread_default()) {
  pipeline_ = gst_pipeline_new("peer");
  webrtc_ = gst_element_factory_make("webrtcbin", "recv");
  g_object_set(webrtc_, "bundle-policy", GST_WEBRTC_BUNDLE_POLICY_MAX_BUNDLE, nullptr);
  gst_bin_add(GST_BIN(pipeline_), webrtc_);
  GstWebRTCICE* ice = nullptr;
  g_object_get(webrtc_, "ice-agent", &ice, nullptr);
  gboolean ok = FALSE;
  g_signal_emit_by_name(ice, "add-local-ip-address", "127.0.0.1", &ok);
  gst_object_unref(ice);

  g_signal_connect(webrtc_, "on-ice-candidate", G_CALLBACK(+[](GstElement*, guint mline, gchar* c, gpointer self) {
                     static_cast<WebRtcPeer*>(self)->post_to_main(
                         {{"type", "ice"}, {"candidate", c}, {"sdpMLineIndex", mline}});
                   }),
                   this);
  g_signal_connect(webrtc_, "on-data-channel", G_CALLBACK(+[](GstElement*, GstWebRTCDataChannel* channel, gpointer self) {
                     g_signal_connect(channel, "on-message-string",
                                      G_CALLBACK(+[](GstWebRTCDataChannel*, gchar* text, gpointer d) {
                                        auto* me = static_cast<WebRtcPeer*>(d);
                                        const auto m = nlohmann::json::parse(text, nullptr, false);
                                        if (!m.is_object() || !m.contains("version")) return;
                                        ++me->frame_messages_;
                                        const std::uint64_t v = m["version"];
                                        if (v > me->version_) me->version_ = v;
                                        if (m.value("level", 0) != 0) ++me->previews_;
                                        else if (v > me->full_version_) me->full_version_ = v;
                                        me->on_water(m);
                                      }),
                                      self);
                   }),
                   this);
  g_signal_connect(webrtc_, "pad-added", G_CALLBACK(+[](GstElement*, GstPad* pad, gpointer data) {
                     auto* self = static_cast<WebRtcPeer*>(data);
                     if (GST_PAD_DIRECTION(pad) != GST_PAD_SRC) return;
                     gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, &WebRtcPeer::on_rtp, self, nullptr);
                     const std::string decode = self->codec_ == "vp8"
                                                    ? "rtpvp8depay ! vp8dec"
                                                    : "rtph264depay ! h264parse ! avdec_h264";
                     GstElement* bin = gst_parse_bin_from_description(
                         (decode + " ! videoconvert ! video/x-raw,format=RGBA ! appsink name=pictures "
                                   "emit-signals=true sync=false max-buffers=2 drop=true")
                             .c_str(),
                         TRUE, nullptr);
                     gst_bin_add(GST_BIN(self->pipeline_), bin);
                     GstElement* sink = gst_bin_get_by_name(GST_BIN(bin), "pictures");
                     g_signal_connect(sink, "new-sample", G_CALLBACK(+[](GstElement* s, gpointer d) {
                                        auto* me = static_cast<WebRtcPeer*>(d);
                                        GstSample* sample = gst_app_sink_pull_sample(GST_APP_SINK(s));
                                        if (!sample) return GST_FLOW_OK;
                                        GstMapInfo map;
                                        GstBuffer* buffer = gst_sample_get_buffer(sample);
                                        const GstStructure* st = gst_caps_get_structure(gst_sample_get_caps(sample), 0);
                                        std::lock_guard lock(me->lock_);
                                        gst_structure_get_int(st, "width", &me->width_);
                                        gst_structure_get_int(st, "height", &me->height_);
                                        gst_buffer_map(buffer, &map, GST_MAP_READ);
                                        me->picture_.assign(map.data, map.data + map.size);
                                        gst_buffer_unmap(buffer, &map);
                                        gst_sample_unref(sample);
                                        ++me->decoded_;
                                        return GST_FLOW_OK;
                                      }),
                                      self);
                     gst_object_unref(sink);
                     gst_element_sync_state_with_parent(bin);
                     GstPad* sinkpad = gst_element_get_static_pad(bin, "sink");
                     gst_pad_link(pad, sinkpad);
                     gst_object_unref(sinkpad);
                   }),
                   this);
  gst_element_set_state(pipeline_, GST_STATE_PLAYING);

  http_ = soup_session_new_with_options("timeout", 10, nullptr);
  SoupMessage* msg = soup_message_new("GET", ws_url.c_str());
  soup_session_websocket_connect_async(http_, msg, nullptr, nullptr, G_PRIORITY_DEFAULT, nullptr, on_socket, this);
  g_object_unref(msg);
}

WebRtcPeer::~WebRtcPeer() {
  hang_up();
  gst_element_set_state(pipeline_, GST_STATE_NULL);
  gst_object_unref(pipeline_);
  g_object_unref(http_);
  while (g_main_context_iteration(context_, FALSE)) {
  }
  g_main_context_unref(context_);
}

void WebRtcPeer::on_socket(GObject* source, GAsyncResult* result, gpointer data) {
  auto* self = static_cast<WebRtcPeer*>(data);
  GError* error = nullptr;
  self->socket_ = soup_session_websocket_connect_finish(SOUP_SESSION(source), result, &error);
  if (error) {
    std::lock_guard lock(self->lock_);
    self->error_ = std::string("websocket: ") + error->message;
    g_error_free(error);
    return;
  }
  g_signal_connect(self->socket_, "message", G_CALLBACK(+[](SoupWebsocketConnection*, gint, GBytes* bytes, gpointer d) {
                     gsize size = 0;
                     const auto* text = static_cast<const char*>(g_bytes_get_data(bytes, &size));
                     static_cast<WebRtcPeer*>(d)->on_message(nlohmann::json::parse(text, text + size, nullptr, false));
                   }),
                   self);
}

void WebRtcPeer::post_to_main(nlohmann::json m) {
  auto* job = new std::pair<WebRtcPeer*, nlohmann::json>(this, std::move(m));
  g_main_context_invoke_full(
      context_, G_PRIORITY_DEFAULT,
      [](gpointer data) -> gboolean {
        auto* j = static_cast<std::pair<WebRtcPeer*, nlohmann::json>*>(data);
        j->first->send(j->second);
        return G_SOURCE_REMOVE;
      },
      job, [](gpointer data) { delete static_cast<std::pair<WebRtcPeer*, nlohmann::json>*>(data); });
}

std::string WebRtcPeer::offer() {
  std::lock_guard lock(lock_);
  return offer_;
}

GstPadProbeReturn WebRtcPeer::on_rtp(GstPad*, GstPadProbeInfo* info, gpointer data) {
  auto* self = static_cast<WebRtcPeer*>(data);
  GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
  if (!gst_rtp_buffer_map(GST_PAD_PROBE_INFO_BUFFER(info), GST_MAP_READ, &rtp)) return GST_PAD_PROBE_OK;
  ++self->rtp_packets_;
  gpointer ext = nullptr;
  guint size = 0;
  const int id = self->playout_delay_id_.load();
  if (id > 0 && gst_rtp_buffer_get_extension_onebyte_header(&rtp, static_cast<guint8>(id), 0, &ext, &size) &&
      size == 3) {
    const auto* b = static_cast<const guint8*>(ext);
    const int min = (b[0] << 4) | (b[1] >> 4), max = ((b[1] & 0x0f) << 8) | b[2];
    if (min == 0 && max == 0) ++self->zero_delay_packets_;
  }
  gst_rtp_buffer_unmap(&rtp);
  return GST_PAD_PROBE_OK;
}

void WebRtcPeer::send(const nlohmann::json& m) {
  if (socket_ && soup_websocket_connection_get_state(socket_) == SOUP_WEBSOCKET_STATE_OPEN)
    soup_websocket_connection_send_text(socket_, m.dump().c_str());
}

void WebRtcPeer::on_message(const nlohmann::json& m) {
  if (!m.is_object()) return;
  const std::string type = m.value("type", "");
  if (type == "offer") {
    const std::string text = m["sdp"].get<std::string>();
    {
      std::lock_guard lock(lock_);
      offer_ = text;
    }
    // a=extmap:<id>[/direction] <uri>
    const std::string uri = " http://www.webrtc.org/experiments/rtp-hdrext/playout-delay";
    for (std::size_t at = text.find("a=extmap:"); at != std::string::npos; at = text.find("a=extmap:", at + 1)) {
      const std::string line = text.substr(at, text.find_first_of("\r\n", at) - at);
      if (line.size() >= uri.size() && line.compare(line.size() - uri.size(), uri.size(), uri) == 0)
        playout_delay_id_ = std::atoi(line.c_str() + 9);
    }
    answer_offer(webrtc_, text, [this](std::string answer) {
      if (answer.empty()) {
        std::lock_guard lock(lock_);
        error_ = "no answer";
        return;
      }
      std::function<std::string(std::string)> edit;
      {
        std::lock_guard lock(lock_);
        edit = edit_answer_;
      }
      post_to_main({{"type", "answer"}, {"sdp", edit ? edit(answer) : answer}});
    });
  } else if (type == "ice") {
    g_signal_emit_by_name(webrtc_, "add-ice-candidate", m["sdpMLineIndex"].get<guint>(),
                          m["candidate"].get<std::string>().c_str());
  } else if (type == "error" || type == "bye") {
    std::lock_guard lock(lock_);
    error_ = m.dump();
  }
}

bool WebRtcPeer::wait_for_frames(int frames, double seconds) {
  const int target = decoded_ + frames;
  const gint64 deadline = g_get_monotonic_time() + static_cast<gint64>(seconds * 1e6);
  while (decoded_ < target && g_get_monotonic_time() < deadline) {
    g_main_context_iteration(context_, FALSE);
    g_usleep(2000);
  }
  return decoded_ >= target;
}

bool WebRtcPeer::wait_for_version(std::uint64_t version, double seconds, bool full_quality) {
  return wait_until(full_quality ? full_version_ : version_, version, seconds);
}

bool WebRtcPeer::wait_for_drops(std::uint64_t drops, double seconds) { return wait_until(water_drops_, drops, seconds); }

bool WebRtcPeer::wait_until(const std::atomic<std::uint64_t>& seen, std::uint64_t value, double seconds) {
  const gint64 deadline = g_get_monotonic_time() + static_cast<gint64>(seconds * 1e6);
  while (seen < value && g_get_monotonic_time() < deadline) {
    g_main_context_iteration(context_, FALSE);
    g_usleep(500);
  }
  return seen >= value;
}

void WebRtcPeer::on_water(const nlohmann::json& m) {
  const auto it = m.find("water");
  if (it == m.end() || !it->is_object()) return;
  std::lock_guard lock(lock_);
  water_ = *it;
  if (it->value("drops", 0ull) > water_drops_) water_drops_ = it->value("drops", 0ull);
}

nlohmann::json WebRtcPeer::last_water() {
  std::lock_guard lock(lock_);
  return water_;
}

std::vector<guint8> WebRtcPeer::last_picture() {
  std::lock_guard lock(lock_);
  return picture_;
}

std::string WebRtcPeer::error() const {
  std::lock_guard lock(const_cast<std::mutex&>(lock_));
  return error_;
}

void WebRtcPeer::hang_up() {
  if (!socket_) return;
  if (soup_websocket_connection_get_state(socket_) == SOUP_WEBSOCKET_STATE_OPEN)
    soup_websocket_connection_close(socket_, SOUP_WEBSOCKET_CLOSE_NORMAL, "bye");
  for (int i = 0; i < 100 && soup_websocket_connection_get_state(socket_) != SOUP_WEBSOCKET_STATE_CLOSED; ++i) {
    g_main_context_iteration(context_, FALSE);
    g_usleep(10000);
  }
  g_object_unref(socket_);
  socket_ = nullptr;
}

void WebRtcPeer::edit_answers(std::function<std::string(std::string)> edit) {
  std::lock_guard lock(lock_);
  edit_answer_ = std::move(edit);
}

}  // namespace caustic::testing
