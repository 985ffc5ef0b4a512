// SPDX-License-Identifier: LGPL-2.1-or-later
// A receiving WebRTC peer for tests: a webrtcbin pinned to 127.0.0.1 that
// answers the server's offer over the real signalling WebSocket, decodes the
// video and keeps the latest picture. Runs on the thread-default main loop.
#pragma once

#include <gst/gst.h>
#include <libsoup/soup.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace caustic::testing {

class WebRtcPeer {
 public:
  /// `codec` picks the decoder (vp8 | h264); `ws_url` is ws://host:port/...signal?token=T.
  WebRtcPeer(const std::string& codec, const std::string& ws_url);
  ~WebRtcPeer();

  /// Iterates the main loop until `frames` more pictures were decoded or
  /// `seconds` passed; returns whether they arrived.
  bool wait_for_frames(int frames, double seconds);

  int decoded() const { return decoded_.load(); }
  std::vector<guint8> last_picture();  // RGBA
  int width() const { return width_; }
  int height() const { return height_; }
  std::string error() const;

  /// Newest parameter version announced on the "frames" data channel (0: none yet).
  std::uint64_t version() const { return version_.load(); }
  int frame_messages() const { return frame_messages_.load(); }
  /// Frame messages of previews (level 1) so far.
  int previews() const { return previews_.load(); }
  /// Iterates the main loop until a frame message with at least `version`
  /// (and level 0 when `full_quality`) arrived or `seconds` passed; returns
  /// whether it did.
  bool wait_for_version(std::uint64_t version, double seconds, bool full_quality = false);

  /// Of a scene with water: the newest frame message's "water" (null
  /// before one), and how many posted drops the frames have shown.
  nlohmann::json last_water();
  std::uint64_t water_drops() const { return water_drops_.load(); }
  /// Iterates the main loop until a frame shows `drops` posted drops or
  /// `seconds` passed; returns whether one did.
  bool wait_for_drops(std::uint64_t drops, double seconds);
  /// The server's offer (SDP text; empty before it came).
  std::string offer();
  /// RTP packets received, and of them those whose playout-delay header
  /// extension (the id the offer gave its URI) asks for no delay: minimum
  /// and maximum 0.
  int rtp_packets() const { return rtp_packets_.load(); }
  int zero_playout_delay_packets() const { return zero_delay_packets_.load(); }
  /// Closes the signalling socket (the server then ends the session).
  void hang_up();
  /// What the peer sends in place of each answer it makes (a test of the
  /// server's checks): `edit` of the answer's SDP text. Set before the offer comes.
  void edit_answers(std::function<std::string(std::string)> edit);

 private:
  static void on_socket(GObject* source, GAsyncResult* result, gpointer self);
  static GstPadProbeReturn on_rtp(GstPad* pad, GstPadProbeInfo* info, gpointer self);
  void on_message(const nlohmann::json& m);
  void send(const nlohmann::json& m);
  void post_to_main(nlohmann::json m);

  std::string codec_;
  std::function<std::string(std::string)> edit_answer_;  // under lock_
  GMainContext* context_;
  GstElement* pipeline_ = nullptr;
  GstElement* webrtc_ = nullptr;
  SoupSession* http_ = nullptr;
  SoupWebsocketConnection* socket_ = nullptr;
  std::atomic<int> decoded_{0};
  std::atomic<std::uint64_t> version_{0};
  std::atomic<std::uint64_t> full_version_{0};
  std::atomic<int> previews_{0};
  std::atomic<std::uint64_t> water_drops_{0};
  nlohmann::json water_;  // under lock_
  void on_water(const nlohmann::json& m);
  bool wait_until(const std::atomic<std::uint64_t>& seen, std::uint64_t value, double seconds);
  std::atomic<int> frame_messages_{0};
  std::atomic<int> rtp_packets_{0}, zero_delay_packets_{0};
  std::atomic<int> playout_delay_id_{0};  // from the offer's a=extmap; 0: none
  std::string offer_;                     // under lock_
  std::mutex lock_;
  std::vector<guint8> picture_;
  int width_ = 0, height_ = 0;
  std::string error_;
};

}  // namespace caustic::testing
