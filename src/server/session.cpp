// SPDX-License-Identifier: LGPL-2.1-or-later
#include "session.hpp"

#include "caustic/gst/causticsrc.hpp"
#include "caustic/gst/stop_pipeline.hpp"
#include "caustic/server/data_files.hpp"
#include "frame_probes.hpp"
#include "h264_level.hpp"
#include "main_queue.hpp"
#include "receive_bins.hpp"
#include "room_messages.hpp"

#define GST_USE_UNSTABLE_API
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <string_view>
#include <thread>

namespace caustic::server {
namespace {

using Ref = std::weak_ptr<Session>;

// A broadcast's frame message with the pool's surface at 16 x 16: 684
// characters of heights, the message under 900 bytes.
constexpr int kBroadcastWaterSide = 16;

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

FrameDatagrams::FrameDatagrams(const std::string& host, int port) {
  GInetAddress* address = g_inet_address_new_from_string(host.c_str());
  if (!address) throw std::runtime_error("not an address: " + host);
  to_ = g_inet_socket_address_new(address, static_cast<guint16>(port));
  socket_ = g_socket_new(g_inet_address_get_family(address), G_SOCKET_TYPE_DATAGRAM, G_SOCKET_PROTOCOL_UDP, nullptr);
  g_object_unref(address);
  if (!socket_) throw std::runtime_error("cannot open a UDP socket");
  g_socket_set_blocking(socket_, FALSE);
}

FrameDatagrams::~FrameDatagrams() {
  if (socket_) g_object_unref(socket_);
  if (to_) g_object_unref(to_);
}

void FrameDatagrams::send(const std::string& text) {
  // A lost frame message is worth nothing: no retry, no error.
  g_socket_send_to(socket_, to_, text.data(), text.size(), nullptr, nullptr);
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
  // The water outlives a pipeline: a reloaded page finds it where it was.
  if (initial.water)
    pool_ = scene_->water ? std::make_shared<water::Pool>(*scene_->water) : std::make_shared<water::Pool>(*initial.water);
}

std::shared_ptr<Session> Session::start(const std::string& id, std::shared_ptr<const GalleryEntry> scene,
                                        SessionOptions options) {
  // The last reference may go on a library's thread: a callback of ICE's
  // own thread (a candidate gathered as the session ends) or of a streaming
  // thread holds one while it runs. Tearing the pipeline down there would
  // free the thread and agent that are calling (not seen to happen; done
  // against a rare crash at stop, docs/reliability.md), so the session is
  // always deleted on the thread that made it, the main loop's.
  std::shared_ptr<Session> session(new Session(id, std::move(scene), std::move(options)), [](Session* s) {
    if (std::this_thread::get_id() == s->owner_thread_) return delete s;
    queue_on(
        s->context_,
        [](gpointer p) -> gboolean {
          delete static_cast<Session*>(p);
          return G_SOURCE_REMOVE;
        },
        s, nullptr);
  });
  session->build();
  return session;
}

void Session::on_main(std::function<void(Session&)> fn) {
  auto* job = new std::pair<Ref, std::function<void(Session&)>>(weak_from_this(), std::move(fn));
  queue_on(
      context_,
      [](gpointer data) -> gboolean {
        auto* j = static_cast<std::pair<Ref, std::function<void(Session&)>>*>(data);
        if (auto s = j->first.lock(); s && !s->closed_) j->second(*s);
        return G_SOURCE_REMOVE;
      },
      job, [](gpointer data) { delete static_cast<std::pair<Ref, std::function<void(Session&)>>*>(data); });
}

void Session::on_pipeline_main(std::function<void(Session&)> fn) {
  on_main([generation = pipeline_generation_.load(), fn = std::move(fn)](Session& me) {
    if (me.pipeline_generation_.load() == generation) fn(me);
  });
}

GstPromise* Session::pipeline_promise(GstPromiseChangeFunc change, gpointer data, GDestroyNotify notify) {
  GstPromise* promise = gst_promise_new_with_change_func(change, data, notify);
  promises_.push_back(gst_promise_ref(promise));
  return promise;
}

void Session::build() {
  const ServerConfig& c = *options_.config;
  const std::map<std::string, std::string> values = {
      {"width", std::to_string(c.width)},
      {"height", std::to_string(c.height)},
      {"framerate", std::to_string(c.framerate)},
      {"bitrate_bps", std::to_string(c.bitrate_kbps * 1000)},
      {"bitrate_kbps", std::to_string(c.bitrate_kbps)},
      {"keyframe_interval", std::to_string(c.keyframe_interval)},
      {"h264_level", h264_level(c.width, c.height, c.framerate, c.bitrate_kbps).name}};
  std::string description = pipeline_description(options_.data_dir, options_.codec, values);
  if (options_.broadcast) {
    // RTP to the Janus mountpoint, RTCP both ways on the next port: Janus
    // latches the sender from its RTCP and passes viewers' PLIs back.
    // An IPv6 address goes in brackets: rtp://::1:5004 is no URI.
    const std::string& host = options_.broadcast->host;
    description += " ! rtpsink name=rtp uri=rtp://" + (host.find(':') != std::string::npos ? "[" + host + "]" : host) +
                   ":" + std::to_string(options_.broadcast->video_port);
  } else {
    description += " ! webrtcbin name=webrtc bundle-policy=max-bundle";
    if (!c.stun_server.empty()) description += " stun-server=" + c.stun_server;
    if (!c.turn_server.empty()) description += " turn-server=" + c.turn_server;
  }

  GError* error = nullptr;
  pipeline_ = gst_parse_launch(description.c_str(), &error);
  if (error) {
    std::string message = error->message;
    g_error_free(error);
    if (pipeline_) gst_object_unref(pipeline_);
    pipeline_ = nullptr;
    throw std::runtime_error("cannot build the " + options_.codec + " pipeline: " + message);
  }
  // The pipeline files are the operator's to edit: elements the server
  // reaches by name are asked for by name, not found missing as a crash.
  for (const char* name : {"src", "encoder", "pay"}) {
    GstElement* element = gst_bin_get_by_name(GST_BIN(pipeline_), name);
    const bool ok = element && (std::string_view(name) != "src" || G_OBJECT_TYPE_NAME(element) == std::string_view("GstCausticSrc"));
    if (element) gst_object_unref(element);
    if (!ok) {
      gst_object_unref(pipeline_);
      pipeline_ = nullptr;
      throw std::runtime_error("the " + options_.codec + " pipeline needs elements named src (a causticsrc), encoder "
                               "and pay");
    }
  }
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline_), "src");
  gst::set_source(src, params_, scene_->levels, pool_);
  g_object_set(src, "progressive", c.settle_ms > 0, "settle-ms", static_cast<guint>(c.settle_ms), "still-interval-ms",
               static_cast<guint>(c.still_interval_ms), nullptr);
  Metrics* metrics = options_.metrics;
  gst::set_frame_observer(src, [metrics](const FrameStats& stats, std::uint64_t) {
    // A tone map redrawn alone (exposure easing) is not a caustic pass.
    if (stats.ray_ms > 0) ++metrics->frames_rendered;
    metrics->render_ms.observe(stats.ray_ms + stats.post_ms);
  });
  gst::set_overrun_observer(src, [metrics] { ++metrics->render_overruns; });
  gst_object_unref(src);
  // The leaky queue before the encoder drops one frame at each overrun.
  if (GstElement* queue = gst_bin_get_by_name(GST_BIN(pipeline_), "encoder_queue")) {
    g_signal_connect(queue, "overrun", G_CALLBACK(+[](GstElement*, gpointer data) {
                       ++static_cast<Metrics*>(data)->frames_dropped;
                     }),
                     metrics);
    gst_object_unref(queue);
  }

  Ref self_ref = weak_from_this();
  pass_key_unit_requests(pipeline_);
  install_frame_probes(pipeline_, metrics, [self_ref](guint32 rtp_timestamp, const FrameFacts& frame) {
    if (auto s = self_ref.lock()) s->tell_frame(rtp_timestamp, frame);
  });

  if (options_.broadcast) {
    frames_out_ = std::make_unique<FrameDatagrams>(options_.broadcast->host, options_.broadcast->data_port);
    alive_now();  // the presenter, who just created it
  } else {
    setup_webrtc();
  }

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
  // A viewer that closes its peer connection ends the data channel's SCTP
  // association, which sctpenc reports as an error: that is the viewer
  // leaving (every browser hang-up), not a fault of the pipeline.
  if (GstObject* from = GST_MESSAGE_SRC(message); from && GST_IS_ELEMENT(from))
    if (GstElementFactory* factory = gst_element_get_factory(GST_ELEMENT(from))) {
      const std::string name = gst_plugin_feature_get_name(GST_PLUGIN_FEATURE(factory));
      if (name == "sctpenc" || name == "sctpdec") {
        log(Level::info, "session " + id_ + ": the viewer closed its connection (the data channel's association ended)",
            log_context());
        if (options_.on_end) options_.on_end(id_, "peer disconnected");
        return;
      }
    }
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

std::optional<std::chrono::steady_clock::time_point> Session::render_heartbeat() const {
  if (!pipeline_) return std::nullopt;
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline_), "src");
  if (!src) return std::nullopt;
  const auto beat = gst::render_heartbeat(src);
  gst_object_unref(src);
  return beat;
}

void Session::tell_frame(guint32 rtp_timestamp, const FrameFacts& frame) {
  nlohmann::json told{{"rtp_timestamp", rtp_timestamp}, {"version", frame.version}, {"level", frame.level}};
  // The surface this frame's caustic came from, for the viewer to draw; a
  // broadcast's is coarser, for its datagram to pass Janus whole (Janus
  // reads at most 1,500 bytes of one).
  if (pool_)
    if (const auto proxy = pool_->proxy(frame.water_step); !proxy.heights.empty())
      told["water"] = water_message(frames_out_ ? water::resample(proxy, kBroadcastWaterSide) : proxy);
  if (frames_out_) {
    frames_out_->send(told.dump());
    // Viewers draw the room (room_messages.hpp) from messages of their own:
    // with a new version's first frame, and each second for viewers who
    // join later.
    const auto now = std::chrono::steady_clock::now();
    if (frame.version != params_told_ || now - params_told_at_ >= std::chrono::seconds(1)) {
      const ParamStore::Snapshot snap = params_->snapshot();
      for (const std::string& text : room_messages(snap.scene, snap.version)) {
        if (text.size() <= kRoomDatagramBytes) {
          frames_out_->send(text);
        } else if (!room_oversize_said_) {  // not seen with the scene format's limits (room_messages_test)
          room_oversize_said_ = true;
          log(Level::warning, "session " + id_ + ": a room message of " + std::to_string(text.size()) +
                                  " bytes does not fit a datagram; viewers draw the picture on the screen alone",
              log_context());
        }
      }
      params_told_ = frame.version;
      params_told_at_ = now;
    }
    return;
  }
  std::lock_guard lock(channel_lock_);
  if (!channel_) return;
  GstWebRTCDataChannelState state;
  g_object_get(channel_, "ready-state", &state, nullptr);
  if (state != GST_WEBRTC_DATA_CHANNEL_STATE_OPEN) return;
  gst_webrtc_data_channel_send_string(channel_, told.dump().c_str());
}

void Session::alive_now(Sign sign) {
  const std::int64_t now = std::chrono::steady_clock::now().time_since_epoch().count();
  alive_ns_.store(now, std::memory_order_relaxed);
  if (sign == Sign::media) media_ns_.store(now, std::memory_order_relaxed);
}

std::string Session::last_media_said() const {
  const std::int64_t then = media_ns_.load(std::memory_order_relaxed);
  if (then == 0) return "no RTCP from it yet";
  const auto ago = std::chrono::steady_clock::now().time_since_epoch() - std::chrono::steady_clock::duration(then);
  return "its last RTCP came " + std::to_string(std::chrono::duration_cast<std::chrono::seconds>(ago).count()) +
         " s ago";
}

std::chrono::steady_clock::time_point Session::last_sign_of_life() const {
  return std::chrono::steady_clock::time_point(
      std::chrono::steady_clock::duration(alive_ns_.load(std::memory_order_relaxed)));
}

void Session::close(const std::string& reason) {
  if (closed_) return;
  closed_ = true;
  say_bye(reason);
  stop();
  std::lock_guard lock(channel_lock_);
  if (channel_) g_object_unref(channel_);
  channel_ = nullptr;
}

void Session::stop() {
  if (!pipeline_) return;
  // What the pipeline's own stop left running (stop_pipeline.hpp), said:
  // each would have kept an ICE agent's sockets for good.
  if (const int left = gst::stop_pipeline(pipeline_))
    log(Level::warning, "session " + id_ + ": " + std::to_string(left) +
                            " elements still ran after the pipeline stopped; stopped them", log_context());
  // A receive bin that holds itself would keep the ICE agent's sockets for
  // good (receive_bins.hpp): rare, and released here, so only said.
  if (webrtc_)
    if (const int held = release_receive_bins(webrtc_))
      log(Level::info, "session " + id_ + ": released " + std::to_string(held) +
                           " WebRTC receive bin(s) that held themselves after the stop", log_context());
}

void Session::teardown_pipeline() {
  {
    std::lock_guard lock(channel_lock_);
    if (channel_) g_object_unref(channel_);
    channel_ = nullptr;
  }
  if (bus_watch_) g_source_remove(bus_watch_);
  bus_watch_ = 0;
  stop();
  // The stopped pipeline's promises still unanswered end (their callbacks
  // see no reply), then all its threads posted, those callbacks' too, is stale.
  for (GstPromise* promise : promises_) {
    gst_promise_expire(promise);
    gst_promise_unref(promise);
  }
  promises_.clear();
  ++pipeline_generation_;
  if (webrtc_) gst_object_unref(webrtc_);
  if (pipeline_) gst_object_unref(pipeline_);
  webrtc_ = nullptr;
  pipeline_ = nullptr;
  offered_ = false;
  offer_sdp_.clear();
  offer_lines_ = 0;
  candidates_ = 0;
  answered_ = false;
  fingerprints_.clear();
}

Session::~Session() {
  close("session closed");
  if (socket_) {
    g_signal_handler_disconnect(socket_, socket_message_);
    g_signal_handler_disconnect(socket_, socket_closed_);
    g_object_unref(socket_);
  }
  if (bus_watch_) g_source_remove(bus_watch_);
  for (GstPromise* promise : promises_) {
    gst_promise_expire(promise);  // its callback finds no session
    gst_promise_unref(promise);
  }
  if (webrtc_) gst_object_unref(webrtc_);
  if (pipeline_) gst_object_unref(pipeline_);
  g_main_context_unref(context_);
}

}  // namespace caustic::server
