// SPDX-License-Identifier: LGPL-2.1-or-later
// One viewer's stream: a pipeline (causticsrc -> encoder -> payloader ->
// webrtcbin) with its own parameters, and the signalling that connects it to
// the viewer's browser. Lives on the GLib main loop's thread; GStreamer
// callbacks from streaming threads are handed over to it.
#pragma once

#include "caustic/image.hpp"
#include "caustic/param_store.hpp"
#include "caustic/pool.hpp"
#include "caustic/server/config.hpp"
#include "dtls_fingerprint.hpp"
#include "frame_probes.hpp"
#include "gallery.hpp"
#include "log.hpp"
#include "metrics.hpp"

#include <gst/gst.h>
#include <libsoup/soup.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <optional>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

// From <gst/webrtc/webrtc.h>, which needs GST_USE_UNSTABLE_API.
typedef struct _GstWebRTCDataChannel GstWebRTCDataChannel;

namespace caustic::server {

/// Where a broadcast session sends its stream (a Janus mountpoint): RTP to
/// video_port (RTCP on the next one), frame messages as datagrams to data_port.
struct RtpTarget {
  std::string host;
  int video_port = 0, data_port = 0;
};

/// Frame messages as UDP datagrams, from the streaming thread.
class FrameDatagrams {
 public:
  FrameDatagrams(const std::string& host, int port);
  ~FrameDatagrams();
  FrameDatagrams(const FrameDatagrams&) = delete;
  FrameDatagrams& operator=(const FrameDatagrams&) = delete;
  void send(const std::string& text);

 private:
  GSocket* socket_ = nullptr;
  GSocketAddress* to_ = nullptr;
};

struct SessionOptions {
  std::string codec;  ///< vp8 | h264
  std::string client_address;  ///< who created it (per-address limits)
  const ServerConfig* config;
  std::filesystem::path data_dir;
  Metrics* metrics;
  std::function<void(const std::string& id, const std::string& reason)> on_end;  ///< asks the owner to remove it
  std::optional<RtpTarget> broadcast;  ///< set: no webrtcbin, the stream goes to a Janus mountpoint
};

class Session : public std::enable_shared_from_this<Session> {
 public:
  /// Builds and starts the pipeline. Throws std::runtime_error on failure.
  static std::shared_ptr<Session> start(const std::string& id, std::shared_ptr<const GalleryEntry> scene,
                                        SessionOptions options);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const std::string& id() const { return id_; }
  const std::string& token() const { return token_; }
  const std::string& codec() const { return options_.codec; }
  const std::string& client_address() const { return options_.client_address; }
  const std::string& scene_id() const { return scene_->id; }
  /// What its log events carry (journald fields under systemd).
  LogContext log_context() const { return {id_, scene_->id, options_.codec, options_.client_address}; }
  ParamStore& params() { return *params_; }
  const GalleryEntry& entry() const { return *scene_; }

  /// The viewer's signalling socket. A second one replaces the first and
  /// gets a fresh stream (a new pipeline, the same parameters) and offer:
  /// a reloaded page is a new peer.
  void attach(SoupWebsocketConnection* socket);
  /// When the attached viewer last showed it is there: a signalling message
  /// or an RTCP packet from its WebRTC receiver. A frozen or vanished
  /// viewer shows neither.
  std::chrono::steady_clock::time_point last_sign_of_life() const;
  /// True while a viewer's socket is attached, and always for a broadcast
  /// (its viewers are Janus's); idle_since() says since when none has been.
  bool connected() const { return socket_ != nullptr || broadcast(); }
  bool broadcast() const { return options_.broadcast.has_value(); }
  /// Notes a sign of life from the session's holder: `request` for a
  /// request with its token or a signalling message, `media` for RTCP
  /// from the viewer's browser.
  enum class Sign { request, media };
  void alive_now(Sign sign = Sign::request);
  /// For the log when a silent session ends: when its RTCP last came.
  std::string last_media_said() const;
  std::chrono::steady_clock::time_point idle_since() const { return idle_since_; }
  /// When the session's render thread last proved alive (main thread);
  /// none before it started. It comes round every few milliseconds even
  /// while no viewer takes frames, so only a stuck render leaves it old.
  std::optional<std::chrono::steady_clock::time_point> render_heartbeat() const;

  /// Sends {"rtp_timestamp", "version", "level"} on the "frames" data
  /// channel, with "water" (water_message()) for a scene with water (any
  /// thread; dropped while the channel is not open).
  void tell_frame(guint32 rtp_timestamp, const FrameFacts& frame);
  /// The session's water (null for a scene without): drops go here.
  water::Pool* water() const { return pool_.get(); }

  /// The picture the session shows as PNG, or EXR when `hdr`, handed to
  /// `done` on the main loop's thread (null when the session has no
  /// picture); never called if the session ends first (frame_api.cpp).
  /// Requests that wait together share one picture, copied and encoded
  /// once on the session's render thread, and one answered less than
  /// kFrameReuse ago serves the next; false (and `done` dropped) when
  /// kMaxFrameWaiters already wait.
  using FrameBytes = std::function<void(const std::vector<unsigned char>* bytes)>;
  bool frame(bool hdr, FrameBytes done);

  /// Tells the viewer the session ends (if connected) and stops the pipeline.
  void close(const std::string& reason);

 private:
  Session(std::string id, std::shared_ptr<const GalleryEntry> scene, SessionOptions options);
  void build();
  void stop();  // the pipeline to NULL, with anything it left running
  void teardown_pipeline();
  void setup_webrtc();
  void send(const nlohmann::json& message);
  // `bye` with `reason`, then the close, on the socket when still open: how
  // every socket the session lets go is told why.
  void say_bye(const std::string& reason);
  void on_socket_message(const std::string& text);
  // Answers a message the session cannot use with an `error` saying why;
  // past kMaxRefusals on one socket, says `bye` and closes it instead.
  void refuse(const std::string& why);
  void negotiate();
  void offer_created(GstPromise* promise);
  // webrtcbin's word on the answer: `refusal` empty when it took it.
  void answer_set(const std::string& refusal);
  // Once DTLS has connected: the viewer's certificate against its answer.
  void dtls_connected(const std::string& pem);
  void on_bus_message(GstMessage* message);
  // Runs `fn` on the main loop's thread if the session still exists.
  void on_main(std::function<void(Session&)> fn);
  // The same for what a pipeline's own threads (webrtcbin's, DTLS's) tell:
  // dropped once that pipeline is torn down, so that a reconnection's new
  // webrtcbin never takes the old one's offer, candidates or verdicts.
  void on_pipeline_main(std::function<void(Session&)> fn);
  // A promise for webrtcbin, kept until the pipeline is torn down: one
  // webrtcbin drops unanswered when it stops would otherwise leak.
  GstPromise* pipeline_promise(GstPromiseChangeFunc change, gpointer data, GDestroyNotify notify);

  std::string id_, token_;
  std::shared_ptr<const GalleryEntry> scene_;
  SessionOptions options_;
  std::shared_ptr<ParamStore> params_;
  std::shared_ptr<water::Pool> pool_;
  GstElement* pipeline_ = nullptr;
  GstElement* webrtc_ = nullptr;
  GMainContext* context_ = nullptr;
  std::thread::id owner_thread_ = std::this_thread::get_id();  // made, and deleted, on the main loop's thread
  guint bus_watch_ = 0;
  SoupWebsocketConnection* socket_ = nullptr;
  gulong socket_message_ = 0, socket_closed_ = 0;
  std::vector<nlohmann::json> outbox_;  // messages that wait for a socket
  std::chrono::steady_clock::time_point idle_since_;
  bool offered_ = false, closed_ = false, had_viewer_ = false;
  std::string offer_sdp_;  // the offer sent to this pipeline's viewer; "" before it
  unsigned offer_lines_ = 0;  // its m-lines
  int candidates_ = 0;        // the viewer's ICE candidates given to this pipeline
  int refusals_ = 0;          // messages of this socket answered with an error
  bool answered_ = false;  // an answer went to webrtcbin (and was not refused)
  // Counts the pipelines torn down: a job a pipeline's thread posts
  // carries the count it saw (read off the main thread, hence atomic).
  std::atomic<std::uint64_t> pipeline_generation_{0};
  std::vector<GstPromise*> promises_;  // pipeline_promise()'s, each a reference
  std::vector<Fingerprint> fingerprints_;  // the answer's, for the viewer's certificate
  std::atomic<std::int64_t> alive_ns_{0};  // steady clock; written from streaming threads too
  std::atomic<std::int64_t> media_ns_{0};  // the same, RTCP alone (0: none yet)
  std::mutex channel_lock_;
  GstWebRTCDataChannel* channel_ = nullptr;  // the "frames" channel
  std::unique_ptr<FrameDatagrams> frames_out_;  // a broadcast's frame messages
  // What a broadcast last told its viewers of the scene (streaming thread only).
  std::uint64_t params_told_ = 0;
  bool room_oversize_said_ = false;
  std::chrono::steady_clock::time_point params_told_at_;
  // frame()'s requests, a batch for each format (PNG, EXR): those waiting,
  // when their picture was asked for, and the last answer (main loop only).
  struct FrameBatch {
    std::vector<FrameBytes> waiting;
    std::chrono::steady_clock::time_point asked, answered;
    std::shared_ptr<const std::vector<unsigned char>> last;
  };
  FrameBatch frames_[2];
};

/// A frame's water surface as the viewer reads it: {"step", "drops", "n",
/// "unit", "heights"}, the heights little-endian int16 in base64.
nlohmann::json water_message(const water::Proxy& proxy);

/// 128 random bits as 32 hex digits (from the system's CSPRNG).
std::string random_hex();

}  // namespace caustic::server
