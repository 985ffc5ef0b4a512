// SPDX-License-Identifier: LGPL-2.1-or-later
// The WebRTC side of a one-viewer session: webrtcbin's set-up, the offer,
// and the signalling WebSocket that carries it to the viewer's browser.
#include "guard_stream.hpp"
#include "ice_setup.hpp"
#include "playout_delay.hpp"
#include "session.hpp"
#include "signal_message.hpp"

#include "caustic/json_text.hpp"

#define GST_USE_UNSTABLE_API
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>

#include <algorithm>
#include <vector>

namespace caustic::server {
namespace {

using Ref = std::weak_ptr<Session>;

// A socket the library or the accept path's guard (guard_stream.hpp) gives
// up on: the library closed it with a bare code (a frame that breaks RFC
// 6455, a text that is not UTF-8), or with none at all (the guard's limits).
// The page is told why first, with `bye` and a close frame of that code and
// a reason; the library then closes no second time. Nothing of the session
// is needed for it, so the handler outlives no one.
void close_saying_why(SoupWebsocketConnection* ws, GError* error, gpointer) {
  if (soup_websocket_connection_get_state(ws) != SOUP_WEBSOCKET_STATE_OPEN) return;
  std::string reason;
  if (error->domain == guard_error_quark())
    reason = error->message;
  else if (error->domain == SOUP_WEBSOCKET_ERROR && error->code == SOUP_WEBSOCKET_CLOSE_PROTOCOL_ERROR)
    reason = "a frame that breaks the WebSocket protocol (RFC 6455): unmasked, reserved bits or opcode, a broken close";
  else if (error->domain == SOUP_WEBSOCKET_ERROR && error->code == SOUP_WEBSOCKET_CLOSE_BAD_DATA)
    reason = "a text message that is not UTF-8";
  else
    return;  // a failed write or read: nobody to tell
  reason.resize(std::min<std::size_t>(reason.size(), 123));  // a close frame's payload is at most 125 bytes
  soup_websocket_connection_send_text(ws, nlohmann::json{{"type", "bye"}, {"reason", reason}}.dump().c_str());
  soup_websocket_connection_close(ws, static_cast<gushort>(error->code), reason.c_str());
}

}  // namespace

void Session::setup_webrtc() {
  const ServerConfig& c = *options_.config;
  webrtc_ = gst_bin_get_by_name(GST_BIN(pipeline_), "webrtc");
  // No playout delay at the viewer (playout_delay.hpp); a broadcast's
  // viewers negotiate with Janus instead, so only a session's own peer.
  GstElement* pay = gst_bin_get_by_name(GST_BIN(pipeline_), "pay");
  if (!add_playout_delay(pay))
    log(Level::warning, "session " + id_ + ": the payloader took no playout-delay extension; the viewer keeps its "
                        "playout delay");
  if (pay) gst_object_unref(pay);
  // Every RTCP packet from the viewer's receiver (receiver reports arrive
  // about once a second from any WebRTC peer) proves it is still there.
  if (GstElement* rtpbin = gst_bin_get_by_name(GST_BIN(webrtc_), "rtpbin")) {
    g_signal_connect_data(
        rtpbin, "on-ssrc-active",
        G_CALLBACK((+[](GstElement*, guint, guint, gpointer data) {
          if (auto s = static_cast<Ref*>(data)->lock()) s->alive_now(Session::Sign::media);
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
        if (auto s = static_cast<Ref*>(data)->lock()) s->on_pipeline_main([](Session& me) { me.negotiate(); });
      })),
      self, [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
  g_signal_connect_data(
      webrtc_, "on-ice-candidate",
      G_CALLBACK((+[](GstElement*, guint mline, gchar* candidate, gpointer data) {
        nlohmann::json message = {{"type", "ice"}, {"candidate", candidate}, {"sdpMLineIndex", mline}};
        if (auto s = static_cast<Ref*>(data)->lock()) s->on_pipeline_main([message](Session& me) { me.send(message); });
      })),
      new Ref(weak_from_this()), [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
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
  GstPromise* promise = pipeline_promise(
      [](GstPromise* p, gpointer data) {
        if (auto s = static_cast<Ref*>(data)->lock()) s->offer_created(p);
      },
      new Ref(weak_from_this()), [](gpointer data) { delete static_cast<Ref*>(data); });
  g_signal_emit_by_name(webrtc_, "create-offer", nullptr, promise);
  gst_promise_unref(promise);
}

void Session::offer_created(GstPromise* promise) {
  if (gst_promise_wait(promise) != GST_PROMISE_RESULT_REPLIED) return;
  const GstStructure* reply = gst_promise_get_reply(promise);
  GstWebRTCSessionDescription* offer = nullptr;
  if (!reply || !gst_structure_has_field(reply, "offer")) {
    on_pipeline_main([](Session& me) {
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
  std::string sdp = text;
  g_free(text);
  const unsigned lines = gst_sdp_message_medias_len(offer->sdp);
  gst_webrtc_session_description_free(offer);
  on_pipeline_main([sdp = std::move(sdp), lines](Session& me) {
    me.offer_sdp_ = sdp;  // what an answer is checked against
    me.offer_lines_ = lines;
    me.send({{"type", "offer"}, {"sdp", sdp}});
  });
}

void Session::answer_set(const std::string& refusal) {
  if (closed_ || !webrtc_) return;
  if (!refusal.empty()) {
    // webrtcbin's words may quote the answer: they go to the log, not back.
    answered_ = false;
    log(Level::info, "session " + id_ + ": webrtcbin refused the answer: " + printable_name(refusal, 200), log_context());
    refuse("answer: the WebRTC stack refused it (its reason is in the server's log)");
    return;
  }
  // The transports DTLS runs on: the first sender's, and the data
  // channel's, the same one when the answer bundles them (browsers do),
  // its own when it does not.
  std::vector<GstWebRTCDTLSTransport*> transports;
  GArray* transceivers = nullptr;
  g_signal_emit_by_name(webrtc_, "get-transceivers", &transceivers);
  GstWebRTCRTPSender* sender = nullptr;
  if (transceivers && transceivers->len > 0)
    g_object_get(g_array_index(transceivers, GstWebRTCRTPTransceiver*, 0), "sender", &sender, nullptr);
  if (transceivers) g_array_unref(transceivers);
  GstWebRTCDTLSTransport* transport = nullptr;
  if (sender) g_object_get(sender, "transport", &transport, nullptr);
  if (sender) gst_object_unref(sender);
  if (transport) transports.push_back(transport);
  GstWebRTCSCTPTransport* sctp = nullptr;
  g_object_get(webrtc_, "sctp-transport", &sctp, nullptr);
  transport = nullptr;
  if (sctp) g_object_get(sctp, "transport", &transport, nullptr);
  if (sctp) gst_object_unref(sctp);
  if (transport && std::find(transports.begin(), transports.end(), transport) == transports.end())
    transports.push_back(transport);
  else if (transport)
    gst_object_unref(transport);
  if (transports.empty()) {
    log(Level::error, "session " + id_ + ": no DTLS transport to check the viewer's certificate on", log_context());
    if (options_.on_end) options_.on_end(id_, "negotiation failed");
    return;
  }
  const auto check = +[](GObject* t, GParamSpec*, gpointer data) {
    GstWebRTCDTLSTransportState state = GST_WEBRTC_DTLS_TRANSPORT_STATE_NEW;
    g_object_get(t, "state", &state, nullptr);
    if (state != GST_WEBRTC_DTLS_TRANSPORT_STATE_CONNECTED) return;
    gchar* pem = nullptr;
    g_object_get(t, "remote-certificate", &pem, nullptr);
    std::string text = pem ? pem : "";
    g_free(pem);
    if (auto s = static_cast<Ref*>(data)->lock()) s->on_pipeline_main([text](Session& me) { me.dtls_connected(text); });
  };
  for (GstWebRTCDTLSTransport* t : transports) {
    g_signal_connect_data(t, "notify::state", G_CALLBACK(check), new Ref(weak_from_this()),
                          [](gpointer data, GClosure*) { delete static_cast<Ref*>(data); }, GConnectFlags(0));
    Ref now(weak_from_this());
    check(G_OBJECT(t), nullptr, &now);  // connected already, before the watch
    gst_object_unref(t);
  }
}

void Session::dtls_connected(const std::string& pem) {
  // Each transport's connection is checked (told twice, it is checked twice).
  if (closed_ || !answered_) return;
  if (certificate_matches(pem, fingerprints_)) return;
  log(Level::warning, "session " + id_ + ": the viewer's DTLS certificate does not match its answer's fingerprint",
      log_context());
  if (options_.on_end) options_.on_end(id_, "the DTLS certificate does not match the answer's fingerprint");
}

void Session::send(const nlohmann::json& message) {
  if (!socket_ || soup_websocket_connection_get_state(socket_) != SOUP_WEBSOCKET_STATE_OPEN) {
    if (outbox_.size() < 256) outbox_.push_back(message);
    return;
  }
  soup_websocket_connection_send_text(socket_, message.dump().c_str());
}

void Session::refuse(const std::string& why) {
  // libsoup queues what it sends without bound: a peer that sends bad
  // messages and reads nothing made the server hold some 200 bytes for each
  // 7-byte message it sent (300 MB for a 10 MB flood).
  if (refusals_ > kMaxRefusals) return;  // closing: the rest are not answered
  if (++refusals_ > kMaxRefusals)
    return say_bye("more than " + std::to_string(kMaxRefusals) + " signalling messages the server cannot use");
  send({{"type", "error"}, {"message", why}});
}

void Session::say_bye(const std::string& reason) {
  if (!socket_ || soup_websocket_connection_get_state(socket_) != SOUP_WEBSOCKET_STATE_OPEN) return;
  soup_websocket_connection_send_text(socket_, nlohmann::json{{"type", "bye"}, {"reason", reason}}.dump().c_str());
  soup_websocket_connection_close(socket_, SOUP_WEBSOCKET_CLOSE_NORMAL, reason.c_str());
}

void Session::attach(SoupWebsocketConnection* socket) {
  if (socket_) {
    g_signal_handler_disconnect(socket_, socket_message_);
    g_signal_handler_disconnect(socket_, socket_closed_);
    say_bye("replaced by a new connection");  // the page knows it was replaced, not dropped
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
  refusals_ = 0;
  alive_now();
  socket_ = G_TYPE_CHECK_INSTANCE_CAST(g_object_ref(socket), SOUP_TYPE_WEBSOCKET_CONNECTION, SoupWebsocketConnection);
  // The limit the accept path's guard holds the socket's frames to: with
  // a fixed 64 KiB here, a larger max_ws_message_bytes cut the socket off
  // at 64 KiB all the same.
  soup_websocket_connection_set_max_incoming_payload_size(socket_, options_.config->max_ws_message_bytes);
  g_signal_connect(socket_, "error", G_CALLBACK(close_saying_why), nullptr);
  socket_message_ = g_signal_connect_data(
      socket_, "message",
      G_CALLBACK((+[](SoupWebsocketConnection*, gint type, GBytes* bytes, gpointer data) {
        auto s = static_cast<Ref*>(data)->lock();
        if (!s) return;
        if (type != SOUP_WEBSOCKET_DATA_TEXT) {
          s->refuse("signalling messages are JSON text, not binary");
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
  const SignalMessage message = parse_signal_message(text, options_.config->max_ws_message_bytes);
  if (const auto* error = std::get_if<SignalError>(&message)) return refuse(error->message);
  alive_now();
  if (const auto* answer = std::get_if<SignalAnswer>(&message)) {
    // webrtcbin refused a second answer only in its debug log.
    if (answered_) return refuse("answer: this offer is answered already (a new connection gets a new offer)");
    // webrtcbin takes the answer's m-lines by position, some mismatches
    // with an abort of the whole process: only a fitting answer reaches it.
    if (const std::string why = answer_mismatch(offer_sdp_, answer->sdp); !why.empty()) return refuse(why);
    answered_ = true;
    fingerprints_ = answer_fingerprints(answer->sdp);
    GstSDPMessage* sdp = nullptr;
    gst_sdp_message_new(&sdp);
    gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(answer->sdp.data()),
                                 static_cast<guint>(answer->sdp.size()), sdp);
    GstWebRTCSessionDescription* description = gst_webrtc_session_description_new(GST_WEBRTC_SDP_TYPE_ANSWER, sdp);
    GstPromise* done = pipeline_promise(
        [](GstPromise* p, gpointer data) {
          std::string refusal;
          if (gst_promise_wait(p) != GST_PROMISE_RESULT_REPLIED) {
            refusal = "no reply";  // the pipeline stopped first
          } else if (const GstStructure* reply = gst_promise_get_reply(p); reply && gst_structure_has_field(reply, "error")) {
            GError* error = nullptr;
            gst_structure_get(reply, "error", G_TYPE_ERROR, &error, nullptr);
            refusal = error ? error->message : "an error";
            if (error) g_error_free(error);
          }
          // For the webrtcbin it was given to: a reconnection may have made another since.
          if (auto s = static_cast<Ref*>(data)->lock())
            s->on_pipeline_main([refusal](Session& me) { me.answer_set(refusal); });
        },
        new Ref(weak_from_this()), [](gpointer data) { delete static_cast<Ref*>(data); });
    g_signal_emit_by_name(webrtc_, "set-remote-description", description, done);
    gst_promise_unref(done);
    gst_webrtc_session_description_free(description);
  } else if (const auto* ice = std::get_if<SignalIce>(&message)) {
    // webrtcbin keeps each candidate it is given (before an answer, or for
    // an m-line it has no transport for) until the next negotiation: only
    // the offer's m-lines take them, and a bounded number a connection.
    if (ice->mline >= offer_lines_) return refuse("ice: the offer has " + std::to_string(offer_lines_) + " m-lines");
    if (ice->candidate.empty()) return;  // end of candidates
    if (candidates_ >= kMaxCandidates) {
      if (candidates_ == kMaxCandidates)  // said once; the count stops one past the limit
        send({{"type", "error"}, {"message", "ice: at most " + std::to_string(kMaxCandidates) + " candidates a connection"}});
      candidates_ = kMaxCandidates + 1;
      return;
    }
    ++candidates_;
    g_signal_emit_by_name(webrtc_, "add-ice-candidate", ice->mline, ice->candidate.c_str());
  }
}

}  // namespace caustic::server
