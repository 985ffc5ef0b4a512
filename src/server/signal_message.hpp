// SPDX-License-Identifier: LGPL-2.1-or-later
// What a viewer may say on the signalling WebSocket, parsed apart from the
// session so that the parser can be tested and fuzzed on its own.
#pragma once

#include "dtls_fingerprint.hpp"

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace caustic::server {

/// The largest signalling message taken unless the configuration's
/// max_ws_message_bytes says otherwise: an SDP answer is a few KiB.
inline constexpr std::size_t kMaxSignalMessageBytes = 64 * 1024;
/// The longest ICE candidate taken, and how many a connection may send.
inline constexpr std::size_t kMaxCandidateBytes = 512;
inline constexpr int kMaxCandidates = 64;
/// An answer's attributes in one m-line, and the parameters of one of its
/// fmtp lines: a browser's have a few dozen and a few.
inline constexpr unsigned kMaxAnswerAttributes = 256;
inline constexpr long kMaxFmtpParameters = 64;
/// Messages a socket may send that the server cannot use: each is answered
/// with an error, and the answers queue for a peer that need not read them.
inline constexpr int kMaxRefusals = 64;

struct SignalAnswer {
  std::string sdp;  ///< checked to be SDP that GStreamer parses
};
struct SignalIce {
  std::string candidate;  ///< empty: the end of the candidates
  unsigned mline = 0;
};
/// A viewer's "I am still here" (the page sends one every few seconds).
struct SignalPing {};
struct SignalError {
  std::string message;  ///< ASCII, never echoes the message's bytes
};

using SignalMessage = std::variant<SignalAnswer, SignalIce, SignalPing, SignalError>;

/// Parses one text message of at most `max_bytes`. Never throws.
SignalMessage parse_signal_message(std::string_view text, std::size_t max_bytes = kMaxSignalMessageBytes);

/// Why `answer` cannot answer `offer` (both SDP text), or "" when it can:
/// one m-line for each of the offer's, in the same order, each of the same
/// media and protocol (a data channel's with its format) and mid; unless
/// rejected (port 0), a sendonly m-line answered recvonly, and ICE
/// credentials, an a=setup of active or passive and a checkable
/// a=fingerprint for each (its own or the session's); candidates of
/// component 1, UDP or TCP with a tcptype; no BUNDLE group or one that starts with the
/// offer's first bundled mid and names only the offer's bundled mids, once
/// each. webrtcbin 1.22 aborts the process on an answer whose RTP m-line
/// sits where its data channel's was, whose mids trade places, or whose
/// BUNDLE group starts with another m-line than the offer's. The reason
/// is ASCII, quotes only the offer (the server's own words), never the
/// answer; an answer that is not SDP is parse_signal_message's to refuse.
std::string answer_mismatch(std::string_view offer, std::string_view answer);

/// The fingerprints of the answer's first m-line not rejected (its own,
/// else the session's): the bundled transport's, which the viewer's DTLS
/// certificate must match. Empty when there are none it can check.
std::vector<Fingerprint> answer_fingerprints(std::string_view answer);

}  // namespace caustic::server
