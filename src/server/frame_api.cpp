// SPDX-License-Identifier: LGPL-2.1-or-later
// GET /api/v1/sessions/{id}/frame.png and frame.exr: what the session shows,
// for a REST client without WebRTC. The picture lives on the session's
// render thread (the GL context is there), so the request is paused, the
// render thread copies and encodes the picture at its next turn (a few
// milliseconds), once for every request then waiting, and the answer is
// written on the main loop. A session that stops first, or a render thread
// that does not come round within kFrameWaitMs, gets 503; requests beyond
// kMaxFrameWaiters at once, 429. Sixty at once once held sixty copies of a
// colour picture (1.2 GB) and encoded each on the main loop.
#include "caustic/gst/causticsrc.hpp"
#include "caustic/image_io.hpp"
#include "http_util.hpp"
#include "log.hpp"
#include "server_state.hpp"

#include <chrono>
#include <memory>
#include <utility>
#include <vector>

namespace caustic::server {
namespace {

constexpr guint kFrameWaitMs = 2000;
// Requests of one format that may wait for a session's next picture at once.
constexpr std::size_t kMaxFrameWaiters = 16;
constexpr auto kFrameReuse = std::chrono::milliseconds(200);

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

// Why a request gets no picture: the session has none (or is stopping),
// its render thread is still on a frame past kFrameWaitMs (a scene that
// takes seconds a frame: the next request may get it), or too many wait.
enum class NoPicture { none_yet, late, crowded };

// `bytes`: the encoded picture, or null with `why`.
void finish(FrameRequest& r, const std::vector<unsigned char>* bytes, NoPicture why = NoPicture::none_yet) {
  if (r.answered) return;
  r.answered = true;
  if (r.timeout) g_source_remove(r.timeout);
  r.timeout = 0;
  if (!bytes) {
    soup_message_headers_replace(soup_server_message_get_response_headers(r.msg), "Retry-After", "1");
    if (why == NoPicture::crowded)
      reply_problem(r.msg, r.state->metrics, 429,
                    std::to_string(kMaxFrameWaiters) + " requests wait for this session's next picture already; retry");
    else if (why == NoPicture::late)
      reply_problem(r.msg, r.state->metrics, SOUP_STATUS_SERVICE_UNAVAILABLE,
                    "the session's renderer did not hand its picture over within " + std::to_string(kFrameWaitMs / 1000) +
                        " s (a frame of this scene takes longer); retry");
    else
      reply_problem(r.msg, r.state->metrics, SOUP_STATUS_SERVICE_UNAVAILABLE, "the session has no picture yet; retry");
  } else {
    reply_bytes(r.msg, SOUP_STATUS_OK, r.hdr ? "image/x-exr" : "image/png", bytes->data(), bytes->size());
    soup_message_headers_replace(soup_server_message_get_response_headers(r.msg), "Cache-Control", "no-store");
  }
  soup_server_message_unpause(r.msg);
}

// The picture in a request's format: PNG, or EXR (a spectral frame's colour
// HDR image as R, G, B, a grey one's as Y). Null when it cannot be encoded.
std::shared_ptr<const std::vector<unsigned char>> encoded(bool hdr, const Rgba8Image& ldr, const HdrImage& grey,
                                                          const RgbHdrImage* colour) {
  try {
    return std::make_shared<const std::vector<unsigned char>>(!hdr     ? encode_png(ldr)
                                                              : colour ? encode_exr(*colour)
                                                                       : encode_exr(grey));
  } catch (const std::exception& e) {
    log(Level::error, std::string("frame: ") + e.what());
    return nullptr;
  }
}

}  // namespace

bool Session::frame(bool hdr, FrameBytes done) {
  FrameBatch& batch = frames_[hdr ? 1 : 0];
  const auto now = std::chrono::steady_clock::now();
  // Pictures asked faster than this are the same picture, near enough: a
  // client polling in a loop costs the render thread an encoding a turn.
  if (batch.last && now - batch.answered < kFrameReuse) {
    done(batch.last.get());
    return true;
  }
  // A picture asked for longer ago than any request waits was never
  // handed over (the session's render thread stuck or gone): those
  // requests have had their 503, and this one asks again.
  if (!batch.waiting.empty() && now - batch.asked >= std::chrono::milliseconds(kFrameWaitMs)) batch.waiting.clear();
  if (batch.waiting.size() >= kMaxFrameWaiters) return false;
  batch.waiting.push_back(std::move(done));
  if (batch.waiting.size() > 1) return true;  // the picture already asked for answers this one too
  batch.asked = now;
  GstElement* src = pipeline_ ? gst_bin_get_by_name(GST_BIN(pipeline_), "src") : nullptr;
  const auto answer = [weak = weak_from_this(), hdr](std::shared_ptr<const std::vector<unsigned char>> bytes) {
    if (auto me = weak.lock())
      me->on_main([hdr, bytes](Session& s) {
        FrameBatch& b = s.frames_[hdr ? 1 : 0];
        if (bytes) b.last = bytes, b.answered = std::chrono::steady_clock::now();
        for (const FrameBytes& waiting : std::exchange(b.waiting, {})) waiting(bytes.get());
      });
  };
  if (!src) {
    answer(nullptr);
    return true;
  }
  // On the render thread, once: the copy and the encoding are the
  // session's own work, not the main loop's, which only writes the bytes.
  gst::request_snapshot(src, [answer, hdr](const Rgba8Image* ldr, const HdrImage* grey, const RgbHdrImage* colour) {
    answer(ldr && grey ? encoded(hdr, *ldr, *grey, colour) : nullptr);
  });
  gst_object_unref(src);
  return true;
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
        finish(r, nullptr, NoPicture::late);
        return G_SOURCE_REMOVE;
      },
      keep, [](gpointer data) { delete static_cast<std::shared_ptr<FrameRequest>*>(data); });
  if (!session.frame(hdr, [request](const std::vector<unsigned char>* bytes) { finish(*request, bytes); }))
    finish(*request, nullptr, NoPicture::crowded);
}

}  // namespace caustic::server
