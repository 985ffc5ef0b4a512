// SPDX-License-Identifier: LGPL-2.1-or-later
// What a refusal says: the message (or, with refused_key, the key) of the
// `Error` that `attempt` throws, or "accepted" when it throws none. Tests
// of bad inputs read refusals through it, so that an input wrongly
// accepted fails on the words it lacks, and any other exception escapes to
// fail the test.
#pragma once

#include <string>
#include <utility>

namespace caustic::testing {

/// What `say` makes of the refusal, or "accepted".
template <class Error, class Attempt, class Say>
std::string refusal(Attempt&& attempt, Say&& say) {
  try {
    std::forward<Attempt>(attempt)();
  } catch (const Error& e) {
    return std::forward<Say>(say)(e);
  }
  return "accepted";
}

template <class Error, class Attempt>
std::string refusal(Attempt&& attempt) {
  return refusal<Error>(std::forward<Attempt>(attempt), [](const Error& e) { return std::string(e.what()); });
}

/// The refusal's key (SceneError::key), or "accepted".
template <class Error, class Attempt>
std::string refused_key(Attempt&& attempt) {
  return refusal<Error>(std::forward<Attempt>(attempt), [](const Error& e) { return e.key(); });
}

}  // namespace caustic::testing
