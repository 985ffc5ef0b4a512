// SPDX-License-Identifier: LGPL-2.1-or-later
// What a refusal says: the message (or, with `say`, the key) of the `Error`
// that `attempt` throws, or "accepted" when it throws none. Tests of bad
// inputs read refusals through it, so that an input wrongly accepted fails
// on the words it lacks, and any other exception escapes to fail the test.
#pragma once

#include <string>
#include <utility>

namespace caustic::testing {

template <class Error, class Attempt>
std::string refusal(Attempt&& attempt) {
  try {
    std::forward<Attempt>(attempt)();
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

/// The refusal's key (SceneError::key), or "accepted".
template <class Error, class Attempt>
std::string refused_key(Attempt&& attempt) {
  try {
    std::forward<Attempt>(attempt)();
  } catch (const Error& e) {
    return e.key();
  }
  return "accepted";
}

}  // namespace caustic::testing
