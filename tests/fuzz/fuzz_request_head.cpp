// SPDX-License-Identifier: LGPL-2.1-or-later
// scan_request_head decides on raw connection bytes before the HTTP library
// sees them, and WebSocketGuard on raw frame bytes; both get the same input.
// Beyond "does not crash" they must not depend on how the bytes arrive:
// the server scans a growing buffer, so a head that is complete in the end
// must look incomplete (not refused) before its blank line, a refusal must
// stand once more bytes come, and the guard's verdict must not change with
// the size of the reads.
#include "caustic/json_text.hpp"
#include "fuzz_support.hpp"
#include "request_head.hpp"

#include <cstdint>
#include <string>

namespace {

namespace s = caustic::server;
using caustic::fuzz::printable_ascii;
using State = s::RequestHead::State;

void check_refusal(const s::RequestHead& head) {
  FUZZ_CHECK(head.status == 400 || head.status == 411 || head.status == 413 || head.status == 417 ||
             head.status == 414 || head.status == 431 ||
             head.status == 501 || head.status == 505);
  FUZZ_CHECK(!head.detail.empty() && printable_ascii(head.detail));
  const std::string answer = s::canned_problem(head.status, head.detail, "Retry-After: 1\r\n");
  FUZZ_CHECK(answer.rfind("HTTP/1.1 " + std::to_string(head.status) + " ", 0) == 0);
  const auto blank = answer.find("\r\n\r\n");
  FUZZ_CHECK(blank != std::string::npos);
  const std::string body = answer.substr(blank + 4);
  FUZZ_CHECK(answer.find("\r\nContent-Length: " + std::to_string(body.size()) + "\r\n") < blank);
  FUZZ_CHECK(caustic::parse_json_text(body).has_value());
}

void check_head(std::string_view bytes, const s::HeadLimits& limits, const s::RequestHead& head) {
  switch (head.state) {
    case State::incomplete:
      FUZZ_CHECK(bytes.size() < limits.max_head_bytes);
      break;
    case State::refused:
      check_refusal(head);
      break;
    case State::complete: {
      FUZZ_CHECK(head.head_bytes >= 4 && head.head_bytes <= bytes.size() && head.head_bytes <= limits.max_head_bytes);
      FUZZ_CHECK(bytes.substr(head.head_bytes - 4, 4) == "\r\n\r\n");
      FUZZ_CHECK(head.content_length <= limits.max_body_bytes);
      // What follows the head (the body) does not change the verdict.
      const auto alone = s::scan_request_head(bytes.substr(0, head.head_bytes), limits);
      FUZZ_CHECK(alone.state == State::complete && alone.head_bytes == head.head_bytes &&
                 alone.content_length == head.content_length && alone.websocket == head.websocket);
      break;
    }
  }
  // The same bytes arriving in two reads: the first half alone.
  const std::size_t cut = head.state == State::complete ? head.head_bytes - 1 : bytes.size() / 2;
  const auto early = s::scan_request_head(bytes.substr(0, cut), limits);
  if (head.state == State::complete) FUZZ_CHECK(early.state == State::incomplete);
  if (early.state == State::refused) FUZZ_CHECK(head.state == State::refused);
}

bool guard_verdict(const std::uint8_t* data, std::size_t size, std::size_t chunk, std::string* error) {
  s::WebSocketGuard guard(1024, 512);
  bool ok = true;
  for (std::size_t i = 0; i < size && ok; i += chunk) ok = guard.feed(data + i, std::min(chunk, size - i));
  FUZZ_CHECK(ok == guard.error().empty());
  if (!ok) FUZZ_CHECK(!guard.feed(data, size));  // a broken limit stays broken
  *error = guard.error();
  return ok;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const s::HeadLimits defaults;
  s::HeadLimits small;
  small.max_head_bytes = 256;
  small.max_headers = 4;
  small.max_body_bytes = 100;
  const auto head = s::scan_request_head(bytes, defaults);
  check_head(bytes, defaults, head);
  const auto tight = s::scan_request_head(bytes, small);
  check_head(bytes, small, tight);
  if (tight.state == State::complete)  // tighter limits never let more through
    FUZZ_CHECK(head.state == State::complete && head.head_bytes == tight.head_bytes &&
               head.content_length == tight.content_length && head.websocket == tight.websocket);

  std::string whole_error, byte_error, split_error;
  const bool whole = guard_verdict(data, size, size ? size : 1, &whole_error);
  const bool bytewise = guard_verdict(data, size, 1, &byte_error);
  const bool split = guard_verdict(data, size, 7, &split_error);
  FUZZ_CHECK(whole == bytewise && whole == split);
  FUZZ_CHECK(whole_error == byte_error && whole_error == split_error);
  FUZZ_CHECK(printable_ascii(whole_error));
  return 0;
}
