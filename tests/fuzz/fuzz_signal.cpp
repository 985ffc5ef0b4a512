// SPDX-License-Identifier: LGPL-2.1-or-later
// parse_signal_message sees every WebSocket text a viewer sends. Whatever
// comes in, the answer is one of the four kinds, and each keeps its promise:
// an answer holds SDP (and is held against an offer without a GLib
// critical), a candidate is printable ASCII with an m-line index
// in range, an error message never echoes the input.
#include "signal_message.hpp"
#include "fuzz_support.hpp"

#include <glib.h>

#include <cstdint>

using caustic::fuzz::printable_ascii;

namespace {
const char* const kOffer =
    "v=0\r\no=- 1 0 IN IP4 0.0.0.0\r\ns=-\r\nt=0 0\r\na=group:BUNDLE video0 application1\r\n"
    "m=video 9 UDP/TLS/RTP/SAVPF 96 97\r\nc=IN IP4 0.0.0.0\r\na=setup:actpass\r\na=sendonly\r\n"
    "a=rtpmap:96 VP8/90000\r\na=mid:video0\r\n"
    "m=application 0 UDP/DTLS/SCTP webrtc-datachannel\r\nc=IN IP4 0.0.0.0\r\na=setup:actpass\r\n"
    "a=mid:application1\r\na=sctp-port:5000\r\n";
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // A GLib critical is a call the library considers a programming error.
  g_log_set_always_fatal(static_cast<GLogLevelFlags>(G_LOG_LEVEL_CRITICAL | G_LOG_LEVEL_ERROR));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace s = caustic::server;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const s::SignalMessage message = s::parse_signal_message(text);
  if (const auto* error = std::get_if<s::SignalError>(&message)) {
    FUZZ_CHECK(!error->message.empty() && printable_ascii(error->message));
  } else if (const auto* answer = std::get_if<s::SignalAnswer>(&message)) {
    FUZZ_CHECK(!answer->sdp.empty());
    FUZZ_CHECK(size <= s::kMaxSignalMessageBytes);
    // Held against an offer in webrtcbin's shape: a reason in ASCII, or none.
    FUZZ_CHECK(printable_ascii(s::answer_mismatch(kOffer, answer->sdp)));
  } else if (const auto* ice = std::get_if<s::SignalIce>(&message)) {
    FUZZ_CHECK(printable_ascii(ice->candidate));
    FUZZ_CHECK(ice->mline <= 63);
  }
  return 0;
}
