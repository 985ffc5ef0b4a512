// SPDX-License-Identifier: LGPL-2.1-or-later
// GET /api/v1/sessions/{id}/frame.png and frame.exr: what the session shows,
// for a REST client without WebRTC. The picture lives on the session's
// render thread (the GL context is there), so the request is paused, the
// render thread copies the picture at its next turn (a few milliseconds),
// and the answer is written on the main loop. A session that stops first,
// or a render thread that does not come round within kFrameWait, gets 503.
#include "caustic/gst/causticsrc.hpp"
#include "caustic/image_io.hpp"
#include "http_util.hpp"
#include "log.hpp"
#include "server_state.hpp"

#include <optional>

namespace caustic::server {
namespace {

constexpr guint kFrameWaitMs = 2000;

// One paused request; the main loop alone touches it.
struct FrameRequest {
  ServerState* state;
  SoupServerMessage* msg;  // owned reference
  bool hdr;
  bool answered = false;
  guint timeout = 0;
  gulong finished = 0;
  FrameRequest(ServerState* state, SoupServerMessage* msg, bool hdr)
      : state(state), msg(SOUP_SERVER_MESSAGE(g_object_ref(msg))), hdr(hdr) {}
  // One owner of the reference: a copy would release it twice.
  FrameRequest(const FrameRequest&) = delete;
  FrameRequest& operator=(const FrameRequest&) = delete;
  ~FrameRequest() {
    if (finished) g_signal_handler_disconnect(msg, finished);
    g_object_unref(msg);
  }
};

// `colour`: a spectral frame's HDR image in colour, which frame.exr then
// carries as R, G, B; null for a grey frame (one channel, Y).
void finish(FrameRequest& r, const Rgba8Image* ldr, const HdrImage* hdr, const RgbHdrImage* colour = nullptr) {
  if (r.answered) return;
  r.answered = true;
  if (r.timeout) g_source_remove(r.timeout);
  r.timeout = 0;
  if (!ldr || !hdr) {
    soup_message_headers_replace(soup_server_message_get_response_headers(r.msg), "Retry-After", "1");
    reply_problem(r.msg, r.state->metrics, SOUP_STATUS_SERVICE_UNAVAILABLE, "the session has no picture yet; retry");
  } else {
    try {
      const auto bytes = !r.hdr ? encode_png(*ldr) : colour ? encode_exr(*colour) : encode_exr(*hdr);
      reply_bytes(r.msg, SOUP_STATUS_OK, r.hdr ? "image/x-exr" : "image/png", bytes.data(), bytes.size());
      soup_message_headers_replace(soup_server_message_get_response_headers(r.msg), "Cache-Control", "no-store");
    } catch (const std::exception& e) {
      log(Level::error, std::string("frame: ") + e.what());
      reply_problem(r.msg, r.state->metrics, SOUP_STATUS_INTERNAL_SERVER_ERROR, "the picture could not be encoded");
    }
  }
  soup_server_message_unpause(r.msg);
}

}  // namespace

void Session::snapshot(std::function<void(const Rgba8Image*, const HdrImage*, const RgbHdrImage*)> done) {
  GstElement* src = pipeline_ ? gst_bin_get_by_name(GST_BIN(pipeline_), "src") : nullptr;
  if (!src) return done(nullptr, nullptr, nullptr);
  auto shared_done = std::make_shared<decltype(done)>(std::move(done));
  gst::request_snapshot(src, [weak = weak_from_this(), shared_done](const Rgba8Image* ldr, const HdrImage* hdr,
                                                                     const RgbHdrImage* colour) {
    // Render thread: copy, then hand over to the main loop (dropped there
    // if the session has ended; the request's timeout answers it).
    struct Pictures {
      Rgba8Image ldr;
      HdrImage hdr;
      std::optional<RgbHdrImage> colour;
    };
    auto pictures = ldr && hdr ? std::make_shared<Pictures>(Pictures{*ldr, *hdr, colour ? std::optional(*colour) : std::nullopt})
                               : nullptr;
    if (auto me = weak.lock())
      me->on_main([shared_done, pictures](Session&) {
        if (!pictures) return (*shared_done)(nullptr, nullptr, nullptr);
        (*shared_done)(&pictures->ldr, &pictures->hdr, pictures->colour ? &*pictures->colour : nullptr);
      });
  });
  gst_object_unref(src);
}

void session_frame(ServerState& s, SoupServerMessage* msg, Session& session, bool hdr) {
  auto request = std::make_shared<FrameRequest>(&s, msg, hdr);
  // A status before returning keeps libsoup's WebSocket handler (registered
  // on /api/v1/sessions) from answering this request itself; the real one
  // replaces it.
  soup_server_message_set_status(msg, SOUP_STATUS_ACCEPTED, nullptr);
  soup_server_message_pause(msg);
  // The client may go away while paused: then nothing more is written.
  request->finished = g_signal_connect(
      msg, "finished",
      G_CALLBACK(+[](SoupServerMessage*, gpointer data) { static_cast<FrameRequest*>(data)->answered = true; }),
      request.get());
  auto* keep = new std::shared_ptr<FrameRequest>(request);
  request->timeout = g_timeout_add_full(
      G_PRIORITY_DEFAULT, kFrameWaitMs,
      [](gpointer data) -> gboolean {
        FrameRequest& r = **static_cast<std::shared_ptr<FrameRequest>*>(data);
        r.timeout = 0;
        finish(r, nullptr, nullptr);
        return G_SOURCE_REMOVE;
      },
      keep, [](gpointer data) { delete static_cast<std::shared_ptr<FrameRequest>*>(data); });
  session.snapshot([request](const Rgba8Image* ldr, const HdrImage* hdr, const RgbHdrImage* colour) {
    finish(*request, ldr, hdr, colour);
  });
}

}  // namespace caustic::server
