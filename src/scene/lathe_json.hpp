// SPDX-License-Identifier: LGPL-2.1-or-later
// A receiver's lathe in JSON (screen_to_json writes it back), kept apart
// from scene_json.cpp, which calls it for that one key.
#pragma once

#include "json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace caustic::detail {

// A lathe's profile: (radius, height) points, at least one off the axis.
inline Lathe read_lathe(Reader r) {
  Lathe l;
  const json* profile = r.get("profile");
  if (!profile || !profile->is_array() || profile->size() < 2 || profile->size() > kMaxLatheProfile)
    throw SceneError(r.key("profile"), "must be an array of 2 to " + std::to_string(kMaxLatheProfile) +
                                           " [radius, height] points");
  double widest = 0;
  for (const json& point : *profile) {
    const auto number = [](const json& x) { return x.is_number() && std::isfinite(x.get<double>()); };
    if (!point.is_array() || point.size() != 2 || !number(point[0]) || !number(point[1]) ||
        point[0].get<double>() < 0 || point[0].get<double>() > kMaxCoordinate ||
        std::abs(point[1].get<double>()) > kMaxCoordinate)
      throw SceneError(r.key("profile"), "each point must be [radius, height]: a radius from 0 to 1e6 and a height "
                                         "of magnitude at most 1e6");
    l.profile.emplace_back(point[0].get<double>(), point[1].get<double>());
    widest = std::max(widest, l.profile.back().x);
  }
  if (!(widest > 0)) throw SceneError(r.key("profile"), "must leave the axis somewhere (a radius above 0)");
  // Every point at one place turns no surface: a receiver of no area.
  if (std::all_of(l.profile.begin(), l.profile.end(), [&](const glm::dvec2& p) { return p == l.profile[0]; }))
    throw SceneError(r.key("profile"), "must not be one point written again: a lathe of no area");
  l.segments = r.integer("segments", l.segments, 3, kMaxLatheSegments);
  r.reject_unknown();
  return l;
}

}  // namespace caustic::detail
