// SPDX-License-Identifier: LGPL-2.1-or-later
// The rectangle light is launched through, for the tracers that start rays
// at the light rather than at the glass: perpendicular to the light's mean
// direction, just in front of the object, covering it. A directional light's
// rays start on it; a point light's pass through it.
#pragma once

#include "caustic/scene.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace caustic {

struct Launch {
  glm::dvec3 origin, a, b;  ///< corner and the two edge vectors
  glm::dvec3 normal;        ///< toward the object: the light's mean direction
};

/// The rectangle covering `points` (world; the object's hull) seen from the
/// light, padded by 1e-3 of its size. Throws SceneError naming
/// light.position when a point light does not have every point in front of
/// it (less than 90 degrees from `centre`'s direction).
Launch launch_rectangle(const Scene& scene, const glm::dvec3& centre, const std::vector<glm::dvec3>& points);

}  // namespace caustic
