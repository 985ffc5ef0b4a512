// SPDX-License-Identifier: LGPL-2.1-or-later
// The head of an HTTP/1.x request, checked before the HTTP library sees a
// byte of it. The library answers broken requests with empty bodies, reads
// whole bodies before a handler can refuse them, takes "+5" or "5, 5" as a
// Content-Length and passes any method bytes on; an exposed server needs one
// strict reading instead, and this is it. Pure functions: tested and fuzzed
// on their own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace caustic::server {

struct HeadLimits {
  std::size_t max_head_bytes = 16 * 1024;  ///< request line and headers
  std::size_t max_headers = 64;
  std::size_t max_body_bytes = 64 * 1024;
  /// POSTs to these paths (as routed_path() gives them) may send up to
  /// max_upload_bytes instead: pictures for the designer. Empty: none.
  std::vector<std::string> upload_paths;
  std::size_t max_upload_bytes = 0;
};

struct RequestHead {
  enum class State { incomplete, complete, refused };
  State state = State::incomplete;
  // complete:
  std::size_t head_bytes = 0;        ///< up to and including the blank line
  std::uint64_t content_length = 0;  ///< 0 when absent
  bool websocket = false;            ///< GET with "Upgrade: websocket"
  /// Where each "Expect" field name of an HTTP/1.0 request starts: such a
  /// client knows no 100 Continue, and the server must ignore the
  /// expectation (RFC 9110 10.1.1), where the library would send one.
  std::vector<std::size_t> ignored_expects;
  // refused:
  unsigned status = 0;  ///< 400, 411, 413, 417 or 431
  std::string detail;   ///< ASCII; never quotes the request's bytes
};

/// Reads the head from the first bytes of a connection. `incomplete` while
/// no blank line has arrived and the limits still allow one.
RequestHead scan_request_head(std::string_view bytes, const HeadLimits& limits);

/// The reason phrase of an HTTP status: libsoup's, or for the statuses it
/// does not know (421, 429, 431) or names as RFC 7231 did (413, 422) their
/// RFC 9110 and 6585 names rather than "Unknown Error" or the old ones.
const char* status_phrase(unsigned status);

/// A whole HTTP/1.1 answer with an RFC 9457 problem body, for refusals made
/// before the HTTP library is involved. `extra_headers` are "Name: value\r\n"
/// lines (for example Retry-After).
std::string canned_problem(unsigned status, const std::string& detail, const std::string& extra_headers = "");

/// Follows the frames a WebSocket client sends and refuses a message (all of
/// its fragments together) or frame larger than the limits: the HTTP
/// library checks each frame alone, so a message in many fragments could
/// otherwise grow without bound.
class WebSocketGuard {
 public:
  WebSocketGuard(std::uint64_t max_message_bytes, std::uint64_t max_frame_bytes)
      : max_message_(max_message_bytes), max_frame_(max_frame_bytes) {}
  /// Feeds received bytes; false (and error()) once the limits are broken.
  bool feed(const unsigned char* data, std::size_t size);
  const std::string& error() const { return error_; }
  /// The close code that error() calls for (RFC 6455 7.4.1): 1009, a
  /// message or frame too large, or 1002, a broken control frame.
  unsigned close_code() const { return close_code_; }
  /// Frames begun so far, control frames included.
  std::uint64_t frames() const { return frames_; }

 private:
  bool header_done();
  std::uint64_t max_message_, max_frame_;
  unsigned char header_[14] = {};
  std::size_t header_have_ = 0, header_need_ = 2;
  std::uint64_t payload_left_ = 0;
  std::uint64_t message_bytes_ = 0;
  std::uint64_t frames_ = 0;
  bool in_payload_ = false;
  std::string error_;
  unsigned close_code_ = 1009;
};

}  // namespace caustic::server
