// SPDX-License-Identifier: LGPL-2.1-or-later
// What a viewer may say on the signalling WebSocket, parsed apart from the
// session so that the parser can be tested and fuzzed on its own.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>

namespace caustic::server {

/// The largest signalling message taken: an SDP answer is a few KiB.
inline constexpr std::size_t kMaxSignalMessageBytes = 64 * 1024;

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

/// Parses one text message. Never throws.
SignalMessage parse_signal_message(std::string_view text);

}  // namespace caustic::server
