// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/launch.hpp"

#include "caustic/optics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace caustic {

Launch launch_rectangle(const Scene& scene, const glm::dvec3& centre, const std::vector<glm::dvec3>& points) {
  const bool point = scene.light.type == LightType::point;
  const glm::dvec3 axis = point ? glm::normalize(centre - scene.light.position) : scene.light.direction;
  const auto [e1, e2] = optics::basis_around(axis);
  // Directional: project along the light. Point: project centrally onto a
  // plane just in front of the nearest point.
  const glm::dvec3 base = point ? scene.light.position : centre;
  double depth = std::numeric_limits<double>::infinity();
  for (const auto& c : points) depth = std::min(depth, glm::dot(c - base, axis));
  if (point && !(depth > 0))
    throw SceneError("light.position",
                     "the light's rays are traced from the light, which needs the whole object in front of it (less "
                     "than 90 degrees from the direction to the object's centre)");
  const double plane = point ? 0.999 * depth : depth - 1e-3 * (1 + std::abs(depth));
  double lo1 = 1e300, hi1 = -1e300, lo2 = 1e300, hi2 = -1e300;
  for (const auto& c : points) {
    glm::dvec3 q = c - base;
    if (point) q *= plane / glm::dot(q, axis);
    lo1 = std::min(lo1, glm::dot(q, e1)), hi1 = std::max(hi1, glm::dot(q, e1));
    lo2 = std::min(lo2, glm::dot(q, e2)), hi2 = std::max(hi2, glm::dot(q, e2));
  }
  const double pad1 = 1e-3 * (hi1 - lo1), pad2 = 1e-3 * (hi2 - lo2);
  Launch l;
  l.normal = axis;
  l.origin = base + plane * axis + (lo1 - pad1) * e1 + (lo2 - pad2) * e2;
  l.a = (hi1 - lo1 + 2 * pad1) * e1;
  l.b = (hi2 - lo2 + 2 * pad2) * e2;
  return l;
}

}  // namespace caustic
