// SPDX-License-Identifier: LGPL-2.1-or-later
// Many viewers of one broadcast in one process: each a WebRTC peer of its
// own (webrtcbin: ICE, DTLS, SRTP, RTP jitter buffer) that joins the Janus
// streaming mountpoint through Janus's WebSocket API as the page does
// (web/js/janus_stream.js), and counts the frames it receives (RTP
// timestamps) without decoding them; the first viewer also decodes, to show
// the stream is whole. A page per viewer decodes every frame, which on the
// two cores that also render and forward limited bench/broadcast_bench.mjs
// to 8 viewers; without decoding, Janus's forwarding is what is measured.
//
// Driven by bench/broadcast_many.mjs over stdin and stdout: prints
// "ready N" once N viewers received a frame, then on the line "mark"
// starts a window, and on "report" prints its counts as one JSON line and
// exits. Bounded: --timeout-s ends it whatever comes.
#include <CLI/CLI.hpp>
#include <gst/gst.h>
#include <gst/rtp/rtp.h>
#include <libsoup/soup.h>
#include <nlohmann/json.hpp>

#include "webrtc_answer.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#define GST_USE_UNSTABLE_API
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>

namespace {

using nlohmann::json;

struct Link {
  std::string url, pin, token;
  long long mountpoint = 0;
};

class Viewer {
 public:
  Viewer(int index, const Link& link, SoupSession* http, bool decode);
  ~Viewer();
  int frames() const { return frames_.load(); }
  int decoded() const { return decoded_.load(); }
  // Connection start to first frame, in ms (-1: none yet).
  double join_ms() const { return first_frame_us_ > 0 ? (first_frame_us_ - started_us_) / 1000.0 : -1; }
  const std::string& error() const { return error_; }

 private:
  void send(json m);
  void request(json m, std::function<void(const json&)> then);
  void on_message(const json& m);
  void answer(const std::string& offer);
  static GstPadProbeReturn on_rtp(GstPad*, GstPadProbeInfo* info, gpointer self);

  int index_;
  Link link_;
  bool decode_;
  SoupWebsocketConnection* socket_ = nullptr;
  GstElement* pipeline_ = nullptr;
  GstElement* webrtc_ = nullptr;
  long long session_ = 0, handle_ = 0;
  int next_ = 0;
  guint keepalive_ = 0;
  std::map<std::string, std::function<void(const json&)>> pending_;
  std::atomic<int> frames_{0}, decoded_{0};
  std::atomic<gint64> first_frame_us_{0};
  gint64 started_us_ = g_get_monotonic_time();
  guint32 last_timestamp_ = 0;  // the streaming thread's own
  bool any_timestamp_ = false;
  std::string error_;
};

// Runs `fn` on the main context (webrtcbin's callbacks come on its threads).
void on_main(std::function<void()> fn) {
  g_main_context_invoke_full(
      nullptr, G_PRIORITY_DEFAULT,
      [](gpointer data) -> gboolean {
        (*static_cast<std::function<void()>*>(data))();
        return G_SOURCE_REMOVE;
      },
      new std::function<void()>(std::move(fn)), [](gpointer data) { delete static_cast<std::function<void()>*>(data); });
}

Viewer::Viewer(int index, const Link& link, SoupSession* http, bool decode) : index_(index), link_(link), decode_(decode) {
  pipeline_ = gst_pipeline_new(("viewer" + std::to_string(index)).c_str());
  webrtc_ = gst_element_factory_make("webrtcbin", nullptr);
  g_object_set(webrtc_, "bundle-policy", GST_WEBRTC_BUNDLE_POLICY_MAX_BUNDLE, nullptr);
  gst_bin_add(GST_BIN(pipeline_), webrtc_);
  GstWebRTCICE* ice = nullptr;
  g_object_get(webrtc_, "ice-agent", &ice, nullptr);
  gboolean ok = FALSE;
  // Janus offers its candidate on the namespace's veth (127.0.0.2).
  g_signal_emit_by_name(ice, "add-local-ip-address", "127.0.0.2", &ok);
  // No UPnP port mappings (a thread and SSDP multicast per agent), as the server.
  GObject* agent = nullptr;
  if (g_object_class_find_property(G_OBJECT_GET_CLASS(ice), "agent")) g_object_get(ice, "agent", &agent, nullptr);
  if (agent && g_object_class_find_property(G_OBJECT_GET_CLASS(agent), "upnp")) g_object_set(agent, "upnp", FALSE, nullptr);
  if (agent) g_object_unref(agent);
  gst_object_unref(ice);
  g_signal_connect(webrtc_, "on-ice-candidate", G_CALLBACK((+[](GstElement*, guint mline, gchar* c, gpointer self) {
                     json candidate = {{"candidate", c}, {"sdpMLineIndex", mline}};
                     auto* me = static_cast<Viewer*>(self);
                     on_main([me, candidate] {
                       me->send({{"janus", "trickle"}, {"session_id", me->session_}, {"handle_id", me->handle_},
                                 {"candidate", candidate}});
                     });
                   })),
                   this);
  g_signal_connect(webrtc_, "pad-added", G_CALLBACK((+[](GstElement*, GstPad* pad, gpointer self) {
                     auto* me = static_cast<Viewer*>(self);
                     if (GST_PAD_DIRECTION(pad) != GST_PAD_SRC) return;
                     gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, &Viewer::on_rtp, me, nullptr);
                     GstCaps* caps = gst_pad_get_current_caps(pad);
                     const gchar* name = caps ? gst_structure_get_string(gst_caps_get_structure(caps, 0), "encoding-name") : nullptr;
                     const bool vp8 = name && g_str_equal(name, "VP8");
                     if (caps) gst_caps_unref(caps);
                     const std::string tail = !me->decode_ ? "fakesink sync=false async=false"
                                              : vp8 ? "rtpvp8depay ! vp8dec ! fakesink name=pictures signal-handoffs=true sync=false async=false"
                                                    : "rtph264depay ! h264parse ! avdec_h264 ! fakesink name=pictures signal-handoffs=true sync=false async=false";
                     GstElement* bin = gst_parse_bin_from_description(tail.c_str(), TRUE, nullptr);
                     gst_bin_add(GST_BIN(me->pipeline_), bin);
                     if (GstElement* sink = gst_bin_get_by_name(GST_BIN(bin), "pictures")) {
                       g_signal_connect(sink, "handoff", G_CALLBACK(+[](GstElement*, GstBuffer*, GstPad*, gpointer v) {
                                          ++static_cast<Viewer*>(v)->decoded_;
                                        }),
                                        me);
                       gst_object_unref(sink);
                     }
                     gst_element_sync_state_with_parent(bin);
                     GstPad* sink_pad = gst_element_get_static_pad(bin, "sink");
                     gst_pad_link(pad, sink_pad);
                     gst_object_unref(sink_pad);
                   })),
                   this);
  gst_element_set_state(pipeline_, GST_STATE_PLAYING);

  SoupMessage* message = soup_message_new("GET", link.url.c_str());
  const char* protocols[] = {"janus-protocol", nullptr};
  soup_session_websocket_connect_async(
      http, message, nullptr, const_cast<char**>(protocols), G_PRIORITY_DEFAULT, nullptr,
      [](GObject* source, GAsyncResult* result, gpointer self) {
        auto* me = static_cast<Viewer*>(self);
        GError* error = nullptr;
        me->socket_ = soup_session_websocket_connect_finish(SOUP_SESSION(source), result, &error);
        if (error) {
          me->error_ = std::string("websocket: ") + error->message;
          g_error_free(error);
          return;
        }
        soup_websocket_connection_set_max_incoming_payload_size(me->socket_, 0);
        g_signal_connect(me->socket_, "message", G_CALLBACK(+[](SoupWebsocketConnection*, gint, GBytes* bytes, gpointer v) {
                           gsize size = 0;
                           const auto* text = static_cast<const char*>(g_bytes_get_data(bytes, &size));
                           static_cast<Viewer*>(v)->on_message(json::parse(text, text + size, nullptr, false));
                         }),
                         me);
        // create, attach, watch (Janus answers the watch with its offer).
        me->request({{"janus", "create"}}, [me](const json& created) {
          me->session_ = created["data"]["id"];
          me->keepalive_ = g_timeout_add_seconds(25, [](gpointer v) -> gboolean {
            auto* viewer = static_cast<Viewer*>(v);
            viewer->send({{"janus", "keepalive"}, {"session_id", viewer->session_}});
            return G_SOURCE_CONTINUE;
          }, me);
          me->request({{"janus", "attach"}, {"session_id", me->session_}, {"plugin", "janus.plugin.streaming"}},
                      [me](const json& attached) {
                        me->handle_ = attached["data"]["id"];
                        me->request({{"janus", "message"}, {"session_id", me->session_}, {"handle_id", me->handle_},
                                     {"body", {{"request", "watch"}, {"id", me->link_.mountpoint}, {"pin", me->link_.pin}}}},
                                    [me](const json& watched) {
                                      if (!watched.contains("jsep")) {
                                        me->error_ = "watch refused: " + watched.dump();
                                        return;
                                      }
                                      me->answer(watched["jsep"]["sdp"]);
                                    });
                      });
        });
      },
      this);
}

Viewer::~Viewer() {
  if (keepalive_) g_source_remove(keepalive_);
  if (socket_) {
    if (soup_websocket_connection_get_state(socket_) == SOUP_WEBSOCKET_STATE_OPEN)
      soup_websocket_connection_close(socket_, SOUP_WEBSOCKET_CLOSE_NORMAL, nullptr);
    g_object_unref(socket_);
  }
  gst_element_set_state(pipeline_, GST_STATE_NULL);
  gst_object_unref(pipeline_);
}

void Viewer::send(json m) {
  if (!socket_ || soup_websocket_connection_get_state(socket_) != SOUP_WEBSOCKET_STATE_OPEN) return;
  m["token"] = link_.token;
  if (!m.contains("transaction")) m["transaction"] = "v" + std::to_string(index_) + "-" + std::to_string(++next_);
  soup_websocket_connection_send_text(socket_, m.dump().c_str());
}

void Viewer::request(json m, std::function<void(const json&)> then) {
  const std::string transaction = "v" + std::to_string(index_) + "-" + std::to_string(++next_);
  m["transaction"] = transaction;
  pending_[transaction] = std::move(then);
  send(std::move(m));
}

// A request's answer: "success", or for a plugin message the event after its "ack".
void Viewer::on_message(const json& m) {
  if (!m.is_object() || m.value("janus", "") == "ack") return;
  const auto it = pending_.find(m.value("transaction", ""));
  if (it == pending_.end()) return;
  auto then = std::move(it->second);
  pending_.erase(it);
  if (m.value("janus", "") == "error") {
    error_ = m.dump();
    return;
  }
  then(m);
}

void Viewer::answer(const std::string& offer_text) {
  caustic::testing::answer_offer(webrtc_, offer_text, [this](std::string sdp_text) {
    if (sdp_text.empty()) return on_main([this] { error_ = "no answer"; });
    on_main([this, sdp_text] {
      request({{"janus", "message"}, {"session_id", session_}, {"handle_id", handle_},
               {"body", {{"request", "start"}}}, {"jsep", {{"type", "answer"}, {"sdp", sdp_text}}}},
              [](const json&) {});
    });
  });
}

// A frame is the packets of one RTP timestamp.
GstPadProbeReturn Viewer::on_rtp(GstPad*, GstPadProbeInfo* info, gpointer self) {
  auto* me = static_cast<Viewer*>(self);
  GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
  if (!gst_rtp_buffer_map(GST_PAD_PROBE_INFO_BUFFER(info), GST_MAP_READ, &rtp)) return GST_PAD_PROBE_OK;
  const guint32 timestamp = gst_rtp_buffer_get_timestamp(&rtp);
  gst_rtp_buffer_unmap(&rtp);
  if (!me->any_timestamp_ || timestamp != me->last_timestamp_) {
    if (!me->any_timestamp_) me->first_frame_us_ = g_get_monotonic_time();
    me->any_timestamp_ = true;
    me->last_timestamp_ = timestamp;
    ++me->frames_;
  }
  return GST_PAD_PROBE_OK;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"N WebRTC viewers of one Janus streaming mountpoint, counting frames (bench/broadcast_many.mjs)"};
  Link link;
  int viewers = 50;
  double timeout_s = 300, join_interval_ms = 100;
  app.add_option("--janus", link.url, "Janus WebSocket URL")->required();
  app.add_option("--mountpoint", link.mountpoint, "mountpoint id")->required();
  app.add_option("--pin", link.pin, "mountpoint pin")->required();
  app.add_option("--token", link.token, "viewer token")->required();
  app.add_option("--viewers", viewers, "how many")->check(CLI::Range(1, 500));
  app.add_option("--join-interval-ms", join_interval_ms, "between two viewers' joins")->check(CLI::Range(0.0, 10000.0));
  app.add_option("--timeout-s", timeout_s, "ends the run whatever comes")->check(CLI::Range(1.0, 3600.0));
  CLI11_PARSE(app, argc, argv);

  gst_init(&argc, &argv);
  SoupSession* http = soup_session_new();
  std::vector<std::unique_ptr<Viewer>> all;
  std::vector<int> marked;
  gint64 marked_us = 0;
  bool ready_said = false;
  const gint64 deadline = g_get_monotonic_time() + static_cast<gint64>(timeout_s * 1e6);

  // Joins one at a time, as an audience arrives, not all in one instant.
  gint64 next_join = g_get_monotonic_time();
  GIOChannel* in = g_io_channel_unix_new(0);
  std::string line;
  bool report = false;
  g_io_add_watch(in, GIOCondition(G_IO_IN | G_IO_HUP), [](GIOChannel* c, GIOCondition, gpointer data) -> gboolean {
    gchar* text = nullptr;
    if (g_io_channel_read_line(c, &text, nullptr, nullptr, nullptr) != G_IO_STATUS_NORMAL) {
      *static_cast<std::string*>(data) = "report";
      return G_SOURCE_REMOVE;
    }
    *static_cast<std::string*>(data) = g_strstrip(text);
    g_free(text);
    return G_SOURCE_CONTINUE;
  }, &line);

  while (!report && g_get_monotonic_time() < deadline) {
    g_main_context_iteration(nullptr, FALSE);
    g_usleep(1000);
    if (static_cast<int>(all.size()) < viewers && g_get_monotonic_time() >= next_join) {
      all.push_back(std::make_unique<Viewer>(static_cast<int>(all.size()), link, http, all.empty()));
      next_join = g_get_monotonic_time() + static_cast<gint64>(join_interval_ms * 1000);
    }
    const int receiving = static_cast<int>(std::count_if(all.begin(), all.end(), [](const auto& v) { return v->frames() > 0; }));
    if (!ready_said && receiving == viewers) {
      std::printf("ready %d\n", receiving);
      std::fflush(stdout);
      ready_said = true;
    }
    if (line == "mark") {
      marked.clear();
      for (const auto& v : all) marked.push_back(v->frames());
      marked.push_back(all.empty() ? 0 : all[0]->decoded());
      marked_us = g_get_monotonic_time();
    }
    report = line == "report";
    line.clear();
  }
  json out = {{"viewers", all.size()}, {"window_s", marked_us ? (g_get_monotonic_time() - marked_us) / 1e6 : 0.0}};
  json frames = json::array(), joins = json::array(), errors = json::array();
  for (std::size_t i = 0; i < all.size(); ++i) {
    frames.push_back(all[i]->frames() - (i < marked.size() ? marked[i] : 0));
    joins.push_back(all[i]->join_ms());
    if (!all[i]->error().empty()) errors.push_back(all[i]->error());
  }
  out["frames"] = frames;
  out["join_ms"] = joins;
  out["errors"] = errors;
  out["decoded_first"] = all.empty() ? 0 : all[0]->decoded() - (marked.empty() ? 0 : marked.back());
  std::printf("%s\n", out.dump().c_str());
  std::fflush(stdout);
  all.clear();
  g_io_channel_unref(in);
  g_object_unref(http);
  return 0;
}
