// SPDX-License-Identifier: LGPL-2.1-or-later
// parse_json_text is the gate for every JSON text from outside, so beyond
// "does not crash" it must keep its promises: accepted text nests no deeper
// than asked, re-parses from its own dump to the same value, and an error
// message never carries the input's bytes.
#include "caustic/json_text.hpp"
#include "fuzz_support.hpp"

#include <algorithm>
#include <cstdint>

namespace {

using caustic::fuzz::printable_ascii;
using nlohmann::json;

// Depth as the parser counts it: a scalar is 0, a container 1 + its deepest child.
int depth(const json& value) {
  if (!value.is_structured()) return 0;
  int deepest = 0;
  for (const auto& child : value) deepest = std::max(deepest, depth(child));
  return 1 + deepest;
}

void check_error(const caustic::JsonTextError& error, std::size_t size) {
  FUZZ_CHECK(!error.message.empty());
  FUZZ_CHECK(printable_ascii(error.message));
  FUZZ_CHECK(error.offset <= size);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  caustic::JsonTextError error;
  const auto value = caustic::parse_json_text(text, &error);
  // A small limit as well, so that the depth check itself is exercised.
  constexpr int kSmallDepth = 3;
  caustic::JsonTextError small_error;
  const auto small = caustic::parse_json_text(text, &small_error, kSmallDepth);

  if (!value) {
    check_error(error, size);
    FUZZ_CHECK(!small);
    check_error(small_error, size);
    return 0;
  }
  FUZZ_CHECK(text.find('\0') == std::string_view::npos);
  const int d = depth(*value);
  FUZZ_CHECK(d <= caustic::kMaxJsonDepth);
  FUZZ_CHECK(small.has_value() == (d <= kSmallDepth));
  if (small) FUZZ_CHECK(*small == *value);
  if (!small) check_error(small_error, size);

  const std::string dumped = caustic::dump_json(*value);
  const auto again = caustic::parse_json_text(dumped);
  FUZZ_CHECK(again.has_value());
  FUZZ_CHECK(*again == *value);
  FUZZ_CHECK(caustic::dump_json(*again) == dumped);
  return 0;
}
