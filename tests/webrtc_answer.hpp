// SPDX-License-Identifier: LGPL-2.1-or-later
// The answering side of an offer, for the peers that stand in for viewers
// (the test peer, the broadcast bench's audience): set the remote offer,
// create the answer, set it as local. What carries the answer back (our
// signalling, Janus's API) stays with the caller.
#pragma once

#ifndef GST_USE_UNSTABLE_API
#define GST_USE_UNSTABLE_API
#endif
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>

#include <functional>
#include <string>

namespace caustic::testing {

/// Answers `offer_sdp` on `webrtc`; `done` gets the answer's SDP text, or ""
/// when webrtcbin made none, on one of webrtcbin's threads.
inline void answer_offer(GstElement* webrtc, const std::string& offer_sdp, std::function<void(std::string)> done) {
  GstSDPMessage* sdp = nullptr;
  gst_sdp_message_new_from_text(offer_sdp.c_str(), &sdp);
  GstWebRTCSessionDescription* offer = gst_webrtc_session_description_new(GST_WEBRTC_SDP_TYPE_OFFER, sdp);
  GstPromise* set = gst_promise_new();
  g_signal_emit_by_name(webrtc, "set-remote-description", offer, set);
  gst_promise_wait(set);
  gst_promise_unref(set);
  gst_webrtc_session_description_free(offer);
  struct Job {
    GstElement* webrtc;
    std::function<void(std::string)> done;
  };
  GstPromise* promise = gst_promise_new_with_change_func(
      [](GstPromise* p, gpointer data) {
        auto* job = static_cast<Job*>(data);
        const GstStructure* reply = gst_promise_get_reply(p);
        GstWebRTCSessionDescription* answer = nullptr;
        if (reply) gst_structure_get(reply, "answer", GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &answer, nullptr);
        gst_promise_unref(p);
        if (!answer) return job->done("");
        GstPromise* local = gst_promise_new();
        g_signal_emit_by_name(job->webrtc, "set-local-description", answer, local);
        gst_promise_unref(local);
        gchar* text = gst_sdp_message_as_text(answer->sdp);
        const std::string answer_sdp = text;
        g_free(text);
        gst_webrtc_session_description_free(answer);
        job->done(answer_sdp);
      },
      new Job{webrtc, std::move(done)}, [](gpointer data) { delete static_cast<Job*>(data); });
  g_signal_emit_by_name(webrtc, "create-answer", nullptr, promise);
}

}  // namespace caustic::testing
