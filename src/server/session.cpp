// SPDX-License-Identifier: LGPL-2.1-or-later
#include "session.hpp"

#include "caustic/gst/causticsrc.hpp"
#include "caustic/server/data_files.hpp"
#include "frame_probes.hpp"
#include "ice_setup.hpp"
#include "signal_message.hpp"

#define GST_USE_UNSTABLE_API
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <random>

namespace caustic::server {
namespace {

using Ref = std::weak_ptr<Session>;

}  // namespace

std::string random_hex() {
  std::random_device device;  // /dev/urandom on Linux
  std::string out;
  for (int i = 0; i < 4; ++i) {
    char buf[9];
    std::snprintf(buf, sizeof buf, "%08x", device());
    out += buf;
  }
  return out;
}

Session::Session(std::string id, std::shared_ptr<const GalleryEntry> scene, SessionOptions options)
    : id_(std::move(id)), token_(random_hex()), scene_(std::move(scene)), options_(std::move(options)),
      context_(g_main_context_ref_thread_default()), idle_since_(std::chrono::steady_clock::now()) {
  Scene initial = scene_->scene;
  auto entry = scene_;
  params_ = std::make_shared<ParamStore>(
      initial,
      [entry](const Scene& candidate) { check_geometry_public(candidate, *entry->levels); },
      [entry](Scene candidate) { return resolve_for(*entry, std::move(candidate)); });
}

std::shared_ptr<Session> Session::start(const std::string& id, std::shared_ptr<const GalleryEntry> scene,
                                        SessionOptions options) {
  std::shared_ptr<Session> session(new Session(id, std::move(scene), std::move(options)));
  session->build();
  return session;
}

void Session::on_main(std::function<void(Session&)> fn) {
  auto* job = new std::pair<Ref, std::function<void(Session&)>>(weak_from_this(), std::move(fn));
  g_main_context_invoke_full(
      context_, G_PRIORITY_DEFAULT,
      [](gpointer data) -> gboolean {
        auto* j = static_cast<std::pair<Ref, std::function<void(Session&)>>*>(data);
        if (auto s = j->first.lock(); s && !s->closed_) j->second(*s);
        return G_SOURCE_REMOVE;
      },
      job, [](gpointer data) { delete static_cast<std::pair<Ref, std::function<void(Session&)>>*>(data); });
}

void Session::build() {
  const ServerConfig& c = *options_.config;
  const int macroblocks = ((c.width + 15) / 16) * ((c.height + 15) / 16);
  const std::map<std::string, std::string> values = {
      {"width", std::to_string(c.width)},
      {"height", std::to_string(c.height)},
      {"framerate", std::to_string(c.framerate)},
      {"bitrate_bps", std::to_string(c.bitrate_kbps * 1000)},
      {"bitrate_kbps", std::to_string(c.bitrate_kbps)},
      {"keyframe_interval", std::to_string(c.keyframe_interval)},
      {"h264_level", macroblocks <= 3600 ? "3.1" : "4"}};
  std::string description = pipeline_description(options_.data_dir, options_.codec, values) +
                            " ! webrtcbin name=webrtc bundle-policy=max-bundle";
  if (!c.stun_server.empty()) description += " stun-server=" + c.stun_server;
  if (!c.turn_server.empty()) description += " turn-server=" + c.turn_server;

  GError* error = nullptr;
  pipeline_ = gst_parse_launch(description.c_str(), &error);
  if (error) {
    std::string message = error->message;
    g_error_free(error);
    if (pipeline_) gst_object_unref(pipeline_);
    pipeline_ = nullptr;
    throw std::runtime_error("cannot build the " + options_.codec + " pipeline: " + message);
  }
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline_), "src");
  gst::set_source(src, params_, scene_->levels);
  g_object_set(src, "progressive", c.settle_ms > 0, "settle-ms", static_cast<guint>(c.settle_ms), "still-interval-ms",
               static_cast<guint>(c.still_interval_ms), nullptr);
  Metrics* metrics = options_.metrics;
  gst::set_frame_observer(src, [metrics](const FrameStats& stats, std::uint64_t) {
    ++metrics->frames_rendered;
    metrics->render_ms.observe(stats.ray_ms + stats.post_ms);
  });
  gst::set_overrun_observer(src, [metrics] { ++metrics->render_overruns; });
  gst_object_unref(src);

  Ref self_ref = weak_from_this();
  pass_key_unit_requests(pipeline_);
  install_frame_probes(pipeline_, metrics, [self_ref](guint32 rtp_timestamp, std::uint64_t version, std::uint32_t level) {
    if (auto s = self_ref.lock()) s->tell_frame(rtp_timestamp, version, level);
  });

  webrtc_ = gst_bin_get_by_name(GST_BIN(pipeline_), "webrtc");
  // Every RTCP packet from the viewer's receiver (receiver reports arrive
  // about once a second from any WebRTC peer) proves it is still there.
  if (GstElement* rtpbin = gst_bin_get_by_name(GST_BIN(webrtc_), "rtpbin")) {
    g_signal_connect_data(
        rtpbin, "on-ssrc-active",
        G_CALLBACK((+[](GstElement*, guint, guint, gpointer data) {
          if (auto s = static_cast<Ref*>(data)->lock()) s->alive_now();
        })),
        new Ref(weak_from_this()), [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
    gst_object_unref(rtpbin);
  } else {
    log(Level::warning, "session " + id_ + ": no rtpbin inside webrtcbin; only signalling pings show the viewer alive");
  }
  for (const auto& refused : configure_ice(webrtc_, c))
    log(Level::warning, "session " + id_ + ": ICE refused local address " + refused, log_context());
  GArray* transceivers = nullptr;
  g_signal_emit_by_name(webrtc_, "get-transceivers", &transceivers);
  for (guint i = 0; transceivers && i < transceivers->len; ++i) {
    auto* t = g_array_index(transceivers, GstWebRTCRTPTransceiver*, i);
    g_object_set(t, "direction", GST_WEBRTC_RTP_TRANSCEIVER_DIRECTION_SENDONLY, "do-nack", TRUE, nullptr);
  }
  if (transceivers) g_array_unref(transceivers);

  auto* self = new Ref(weak_from_this());
  g_signal_connect_data(
      webrtc_, "on-negotiation-needed",
      G_CALLBACK((+[](GstElement*, gpointer data) {
        if (auto s = static_cast<Ref*>(data)->lock()) s->on_main([](Session& me) { me.negotiate(); });
      })),
      self, [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
  g_signal_connect_data(
      webrtc_, "on-ice-candidate",
      G_CALLBACK((+[](GstElement*, guint mline, gchar* candidate, gpointer data) {
        nlohmann::json message = {{"type", "ice"}, {"candidate", candidate}, {"sdpMLineIndex", mline}};
        if (auto s = static_cast<Ref*>(data)->lock()) s->on_main([message](Session& me) { me.send(message); });
      })),
      new Ref(weak_from_this()), [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));

  GstBus* bus = gst_element_get_bus(pipeline_);
  bus_watch_ = gst_bus_add_watch_full(
      bus, G_PRIORITY_DEFAULT,
      [](GstBus*, GstMessage* message, gpointer data) -> gboolean {
        if (auto s = static_cast<Ref*>(data)->lock()) s->on_bus_message(message);
        return G_SOURCE_CONTINUE;
      },
      new Ref(weak_from_this()), [](gpointer data) { delete static_cast<Ref*>(data); });
  gst_object_unref(bus);

  if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("the " + options_.codec + " pipeline does not start");
}

void Session::on_bus_message(GstMessage* message) {
  if (GST_MESSAGE_TYPE(message) != GST_MESSAGE_ERROR || closed_) return;
  GError* error = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(message, &error, &debug);
  const std::string text = std::string(error->message) + (debug ? std::string(" (") + debug + ")" : "");
  g_error_free(error);
  g_free(debug);
  ++options_.metrics->pipeline_errors;
  log(Level::error, "session " + id_ + ": pipeline error: " + text, log_context());
  if (options_.on_end) options_.on_end(id_, "pipeline error");
}

void Session::negotiate() {
  if (offered_ || closed_) return;
  // Offering before the payloader's caps reach webrtcbin can yield no offer
  // (webrtcbin 1.22): wait for caps on its sink pad first.
  GstPad* pad = gst_element_get_static_pad(webrtc_, "sink_0");
  GstCaps* caps = pad ? gst_pad_get_current_caps(pad) : nullptr;
  if (pad) gst_object_unref(pad);
  if (!caps) {
    auto* self = new Ref(weak_from_this());
    g_timeout_add_full(
        G_PRIORITY_DEFAULT, 50,
        [](gpointer data) -> gboolean {
          if (auto s = static_cast<Ref*>(data)->lock()) s->negotiate();
          return G_SOURCE_REMOVE;
        },
        self, [](gpointer data) { delete static_cast<Ref*>(data); });
    return;
  }
  gst_caps_unref(caps);
  offered_ = true;
  // Unordered, unreliable: a late frame message is worth nothing.
  GstStructure* options = gst_structure_new("options", "ordered", G_TYPE_BOOLEAN, FALSE, "max-retransmits", G_TYPE_INT,
                                            0, nullptr);
  GstWebRTCDataChannel* channel = nullptr;
  g_signal_emit_by_name(webrtc_, "create-data-channel", "frames", options, &channel);
  gst_structure_free(options);
  {
    std::lock_guard lock(channel_lock_);
    channel_ = channel;
  }
  GstPromise* promise = gst_promise_new_with_change_func(
      [](GstPromise* p, gpointer data) {
        if (auto s = static_cast<Ref*>(data)->lock()) s->offer_created(p);
        gst_promise_unref(p);
      },
      new Ref(weak_from_this()), [](gpointer data) { delete static_cast<Ref*>(data); });
  g_signal_emit_by_name(webrtc_, "create-offer", nullptr, promise);
}

void Session::offer_created(GstPromise* promise) {
  if (gst_promise_wait(promise) != GST_PROMISE_RESULT_REPLIED) return;
  const GstStructure* reply = gst_promise_get_reply(promise);
  GstWebRTCSessionDescription* offer = nullptr;
  if (!reply || !gst_structure_has_field(reply, "offer")) {
    on_main([](Session& me) {
      log(Level::error, "session " + me.id_ + ": webrtcbin made no offer", me.log_context());
      if (me.options_.on_end) me.options_.on_end(me.id_, "negotiation failed");
    });
    return;
  }
  gst_structure_get(reply, "offer", GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &offer, nullptr);
  GstPromise* done = gst_promise_new();
  g_signal_emit_by_name(webrtc_, "set-local-description", offer, done);
  gst_promise_unref(done);
  gchar* text = gst_sdp_message_as_text(offer->sdp);
  nlohmann::json message = {{"type", "offer"}, {"sdp", text}};
  g_free(text);
  gst_webrtc_session_description_free(offer);
  on_main([message](Session& me) { me.send(message); });
}

std::optional<std::chrono::steady_clock::time_point> Session::render_heartbeat() const {
  if (!pipeline_) return std::nullopt;
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline_), "src");
  if (!src) return std::nullopt;
  const auto beat = gst::render_heartbeat(src);
  gst_object_unref(src);
  return beat;
}

void Session::tell_frame(guint32 rtp_timestamp, std::uint64_t version, std::uint32_t level) {
  std::lock_guard lock(channel_lock_);
  if (!channel_) return;
  GstWebRTCDataChannelState state;
  g_object_get(channel_, "ready-state", &state, nullptr);
  if (state != GST_WEBRTC_DATA_CHANNEL_STATE_OPEN) return;
  const std::string text =
      nlohmann::json{{"rtp_timestamp", rtp_timestamp}, {"version", version}, {"level", level}}.dump();
  gst_webrtc_data_channel_send_string(channel_, text.c_str());
}

void Session::send(const nlohmann::json& message) {
  if (!socket_ || soup_websocket_connection_get_state(socket_) != SOUP_WEBSOCKET_STATE_OPEN) {
    if (outbox_.size() < 256) outbox_.push_back(message);
    return;
  }
  soup_websocket_connection_send_text(socket_, message.dump().c_str());
}

void Session::attach(SoupWebsocketConnection* socket) {
  if (socket_) {
    g_signal_handler_disconnect(socket_, socket_message_);
    g_signal_handler_disconnect(socket_, socket_closed_);
    soup_websocket_connection_close(socket_, SOUP_WEBSOCKET_CLOSE_NORMAL, "replaced by a new connection");
    g_object_unref(socket_);
    socket_ = nullptr;
  }
  if (had_viewer_) {
    // The old peer's offer, ICE state and data channel mean nothing to the
    // new one: start its stream afresh with the same parameters.
    teardown_pipeline();
    outbox_.clear();
    build();
  }
  had_viewer_ = true;
  alive_now();
  socket_ = G_TYPE_CHECK_INSTANCE_CAST(g_object_ref(socket), SOUP_TYPE_WEBSOCKET_CONNECTION, SoupWebsocketConnection);
  soup_websocket_connection_set_max_incoming_payload_size(socket_, kMaxSignalMessageBytes);
  socket_message_ = g_signal_connect_data(
      socket_, "message",
      G_CALLBACK((+[](SoupWebsocketConnection*, gint type, GBytes* bytes, gpointer data) {
        auto s = static_cast<Ref*>(data)->lock();
        if (!s) return;
        if (type != SOUP_WEBSOCKET_DATA_TEXT) {
          s->send({{"type", "error"}, {"message", "signalling messages are JSON text, not binary"}});
          return;
        }
        gsize size = 0;
        const auto* text = static_cast<const char*>(g_bytes_get_data(bytes, &size));
        s->on_socket_message(std::string(text, size));
      })),
      new Ref(weak_from_this()), [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
  socket_closed_ = g_signal_connect_data(
      socket_, "closed",
      G_CALLBACK((+[](SoupWebsocketConnection*, gpointer data) {
        auto s = static_cast<Ref*>(data)->lock();
        if (s && !s->closed_ && s->options_.on_end) s->options_.on_end(s->id_, "peer disconnected");
      })),
      new Ref(weak_from_this()), [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
  std::vector<nlohmann::json> pending;
  pending.swap(outbox_);
  for (const auto& m : pending) send(m);
}

void Session::on_socket_message(const std::string& text) {
  const SignalMessage message = parse_signal_message(text);
  if (const auto* error = std::get_if<SignalError>(&message)) {
    send({{"type", "error"}, {"message", error->message}});
    return;
  }
  alive_now();
  if (const auto* answer = std::get_if<SignalAnswer>(&message)) {
    GstSDPMessage* sdp = nullptr;
    gst_sdp_message_new(&sdp);
    gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(answer->sdp.data()),
                                 static_cast<guint>(answer->sdp.size()), sdp);
    GstWebRTCSessionDescription* description = gst_webrtc_session_description_new(GST_WEBRTC_SDP_TYPE_ANSWER, sdp);
    GstPromise* done = gst_promise_new();
    g_signal_emit_by_name(webrtc_, "set-remote-description", description, done);
    gst_promise_unref(done);
    gst_webrtc_session_description_free(description);
  } else if (const auto* ice = std::get_if<SignalIce>(&message)) {
    if (ice->candidate.empty()) return;  // end of candidates
    g_signal_emit_by_name(webrtc_, "add-ice-candidate", ice->mline, ice->candidate.c_str());
  }
}

void Session::alive_now() {
  alive_ns_.store(std::chrono::steady_clock::now().time_since_epoch().count(), std::memory_order_relaxed);
}

std::chrono::steady_clock::time_point Session::last_sign_of_life() const {
  return std::chrono::steady_clock::time_point(
      std::chrono::steady_clock::duration(alive_ns_.load(std::memory_order_relaxed)));
}

void Session::close(const std::string& reason) {
  if (closed_) return;
  closed_ = true;
  if (socket_) {
    if (soup_websocket_connection_get_state(socket_) == SOUP_WEBSOCKET_STATE_OPEN) {
      soup_websocket_connection_send_text(socket_, nlohmann::json{{"type", "bye"}, {"reason", reason}}.dump().c_str());
      soup_websocket_connection_close(socket_, SOUP_WEBSOCKET_CLOSE_NORMAL, reason.c_str());
    }
  }
  if (pipeline_) gst_element_set_state(pipeline_, GST_STATE_NULL);
  std::lock_guard lock(channel_lock_);
  if (channel_) g_object_unref(channel_);
  channel_ = nullptr;
}

void Session::teardown_pipeline() {
  {
    std::lock_guard lock(channel_lock_);
    if (channel_) g_object_unref(channel_);
    channel_ = nullptr;
  }
  if (bus_watch_) g_source_remove(bus_watch_);
  bus_watch_ = 0;
  if (pipeline_) gst_element_set_state(pipeline_, GST_STATE_NULL);
  if (webrtc_) gst_object_unref(webrtc_);
  if (pipeline_) gst_object_unref(pipeline_);
  webrtc_ = nullptr;
  pipeline_ = nullptr;
  offered_ = false;
}

Session::~Session() {
  close("session closed");
  if (socket_) {
    g_signal_handler_disconnect(socket_, socket_message_);
    g_signal_handler_disconnect(socket_, socket_closed_);
    g_object_unref(socket_);
  }
  if (bus_watch_) g_source_remove(bus_watch_);
  if (webrtc_) gst_object_unref(webrtc_);
  if (pipeline_) gst_object_unref(pipeline_);
  g_main_context_unref(context_);
}

}  // namespace caustic::server
