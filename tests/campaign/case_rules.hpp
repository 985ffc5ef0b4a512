// SPDX-License-Identifier: LGPL-2.1-or-later
// Rules and JSON helpers shared by the two halves of the case generator.
#pragma once

#include <algorithm>

#include "malformed_cases.hpp"

namespace campaign::cases {

using Headers = std::vector<std::pair<std::string, std::string>>;

// Rule: the answer is one of `codes`.
inline auto status_in(std::string name, std::vector<int> codes) {
  return [name = std::move(name), codes = std::move(codes)](KindReport& rep, const Response& r, const std::string& s) {
    rep.check(name, r.kind == Response::Answer && std::find(codes.begin(), codes.end(), r.status) != codes.end(), s);
  };
}

// Rule: the request is refused (an error answer or a closed connection).
inline auto refused(std::string name) {
  return [name = std::move(name)](KindReport& rep, const Response& r, const std::string& s) {
    rep.check(name, r.kind != Response::Answer || r.status >= 400, s);
  };
}

inline void collect(const nlohmann::json& j, std::vector<std::string>& path,
                    std::vector<std::pair<std::vector<std::string>, nlohmann::json>>& out) {
  if (j.is_object() && !j.empty()) {
    for (const auto& [k, v] : j.items()) {
      path.push_back(k);
      collect(v, path, out);
      path.pop_back();
    }
  } else if (!path.empty()) {
    out.emplace_back(path, j);
  }
}

// {"a": {"b": value}} for the path a.b.
inline std::string nest(const std::vector<std::string>& path, const std::string& value_text) {
  std::string out;
  for (const auto& p : path) out.append("{").append(nlohmann::json(p).dump()).append(":");
  out += value_text;
  out += std::string(path.size(), '}');
  return out;
}

}  // namespace campaign::cases
